"""The Gaussians that no training view can tell from the black background: found when training ends, emptied.

Why: on the skull capture (flash, dark room) four test views of nine render as one flat dark colour, 10-13 dB
beside 18-28 for the rest, while the training views reach 37 dB (benchmarks/floaters.py on an H200 at 84176f2:
docs/results/capture/clearance_6590a41.json, `floaters_84176f2`). What covers them are black, opaque Gaussians,
0.2-1.5 across, 0.7-2 from the nearest training camera and inside 5-11 training frustums: in every training view
they are drawn over the photos' black background, where a black Gaussian and no Gaussian give the same pixel, so
the photos never push them away; a view between the cameras sees them in front of the skull. Camera clearance
(they hold no camera) and a size cap relative to the nearest camera (it cost the training views 6-15 dB first) do
not find them.

How: removing one Gaussian changes a pixel by exactly its opacity times the pixel's derivative with respect to it
(a render is affine in each opacity), so one backward pass a channel gives every Gaussian's change summed over a
view, and one through a constant feature its drawn weight. A Gaussian whose change over the training views, per
unit of its weight in them, stays under TOLERANCE is a candidate. The two sheets of a wall seen from both sides
each pass that test (from each side the near one hides the far one), so the candidates are then removed together,
each view rendered without them, and a candidate drawn where that joint removal changed the picture goes back,
until the rest change no training view.

Only for the black training background (`train --background black`, the default): against a random colour a
Gaussian never matches what is behind it. Unseen Gaussians (weight under MIN_WEIGHT in every view) are left as
they are: what stands behind an object belongs to the hole the removal makes, not here.
"""

from __future__ import annotations

import numpy as np
import torch

from engine.formats.cameras import Camera
from engine.io.gaussians import Gaussians
from engine.render.rasterize import CameraTensors, default_backend, rasterize, view_colours

TOLERANCE = 0.01  # mean colour change per unit of drawn weight (0-1 scale): under one 8-bit level on average
MIN_WEIGHT = 1.0  # drawn weight summed over the training views, in pixels at full opacity: less is unseen
ROUNDS = 3  # joint checks: each returns the candidates drawn where removing them all changed a view


def background_floaters(gaussians: Gaussians, cameras: list[Camera], sh_degree: int, device: torch.device,
                        tolerance: float = TOLERANCE, rounds: int = ROUNDS) -> np.ndarray:
    """(N,) bool: the Gaussians whose removal, together, leaves every one of `cameras` as it renders now."""
    gaussians = {k: v.detach().to(device) for k, v in gaussians.items()}
    alone, weight = _alone_change(gaussians, cameras, sh_degree, device)
    removable = (weight >= MIN_WEIGHT) & (alone < tolerance * weight)
    for _ in range(rounds):
        if not removable.any():
            break
        joint = _joint_change(gaussians, removable, cameras, sh_degree, device)
        back = removable & (joint >= tolerance * weight)
        if not back.any():
            break
        removable &= ~back
    return removable.cpu().numpy()


def _alone_change(gaussians: Gaussians, cameras: list[Camera], sh_degree: int, device: torch.device
                  ) -> tuple[torch.Tensor, torch.Tensor]:
    """Per Gaussian, view_change's change and weight summed over `cameras`."""
    n = len(gaussians["means"])
    change, weight = torch.zeros(n, device=device), torch.zeros(n, device=device)
    for camera in cameras:
        view, drawn = view_change(gaussians, camera, sh_degree, device)
        change += view
        weight += drawn
    return change, weight


def view_change(gaussians: Gaussians, camera: Camera, sh_degree: int, device: torch.device
                ) -> tuple[torch.Tensor, torch.Tensor]:
    """Per Gaussian, the colour change its removal alone makes in `camera`'s picture (|summed over the pixels| per
    channel, the channels' mean), and its drawn weight there (pixels at full opacity)."""
    n = len(gaussians["means"])
    backend = default_backend(device)
    tensors = CameraTensors.from_camera(camera, device)
    alpha = torch.sigmoid(gaussians["opacities"].flatten()).clamp(1e-6, 1 - 1e-6).requires_grad_(True)
    live = dict(gaussians, opacities=torch.logit(alpha).reshape(gaussians["opacities"].shape))
    colours = view_colours(gaussians, tensors, sh_degree, backend)
    ones = torch.ones(n, 1, device=device, requires_grad=True)
    out, _, _ = rasterize(live, torch.cat([colours, ones], -1), tensors, backend, depth=False)
    change = torch.zeros(n, device=device)
    for c in range(3):
        (grad,) = torch.autograd.grad(out[..., c].sum(), alpha, retain_graph=True)
        change += (alpha.detach() * grad).abs() / 3
    (drawn,) = torch.autograd.grad(out[..., 3].sum(), ones)
    return change, drawn[:, 0]


def _joint_change(gaussians: Gaussians, removed: torch.Tensor, cameras: list[Camera], sh_degree: int,
                  device: torch.device) -> torch.Tensor:
    """Per Gaussian, its drawn weight times the mean colour change at each pixel when all of `removed` go at once,
    summed over the views."""
    n = len(gaussians["means"])
    backend = default_backend(device)
    rest = {k: v[~removed] for k, v in gaussians.items()}
    total = torch.zeros(n, device=device)
    for camera in cameras:
        tensors = CameraTensors.from_camera(camera, device)
        ones = torch.ones(n, 1, device=device, requires_grad=True)  # its gradient: each Gaussian's drawn weight
        out, _, _ = rasterize(gaussians, torch.cat([view_colours(gaussians, tensors, sh_degree, backend), ones], -1),
                              tensors, backend, depth=False)
        with torch.no_grad():
            without, _, _ = rasterize(rest, view_colours(rest, tensors, sh_degree, backend), tensors, backend,
                                      depth=False)
            changed = (out[..., :3] - without).abs().mean(-1)
        (grad,) = torch.autograd.grad((out[..., 3] * changed).sum(), ones)
        total += grad[:, 0]
    return total
