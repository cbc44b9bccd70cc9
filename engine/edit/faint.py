"""Faint Gaussians the removed object leaves that render only inside its region: the translucent shell of a
shape that stays once the opaque body has gone.

Training hangs faint Gaussians over and around an object's surface (the blend of its edge with what lies behind
it, a halo the densification grew). The identity vote, the visual hull (the region in nine of ten views that frame
a Gaussian's centre) and the loose pieces (off every support, wholly near the object) take most of them; what is
left shows as a ghost of the object in every view where it stood: on the statue capture at a1b3f76, a grey-green
band where the bronze base had sat, 2,523 Gaussians of median opacity 0.11 that none of those rules took
(docs/results/capture/subject_inputs.json, `statue_a1b3f76`).

What marks them is where they render, not where their centres lie: blended over the training views (each
Gaussian's weight in a pixel as the rasterizer composites the scene without the object), a faint Gaussian whose
weight falls inside the object's region in those views by INSIDE_SHARE or more has shown nothing but the object's
place. Only faint ones (opacity under FAINT_OPACITY) and only ones off the supports and other objects: the wall or
table the object hid keeps its Gaussians, however few views saw them.
"""

from __future__ import annotations

import numpy as np
import torch

from engine.base.progress import Progress
from engine.formats.cameras import Camera
from engine.io.gaussians import Gaussians
from engine.render.rasterize import CameraTensors, default_backend, rasterize

FAINT_OPACITY = 0.3  # opacity under which a Gaussian counts as faint (the statue's band: median 0.11, 91% under)
INSIDE_SHARE = 0.9  # share of its rendered weight inside the object's regions that marks it (the hull's share)


def rendered_weights(gaussians: Gaussians, cameras: list[Camera], regions: list[np.ndarray],
                     device: torch.device) -> tuple[np.ndarray, np.ndarray]:
    """(N,) each Gaussian's blended weight (transmittance times alpha, summed over pixels and `cameras`) inside
    the `regions` (one (H, W) bool a camera), and in all. Read as the gradient of the blended image of a
    zero feature: d(sum of pixels)/d(feature_i) is Gaussian i's weight summed over those pixels, on either
    rasterizer, in one backward pass a view."""
    on_device = {k: v.detach().to(device) for k, v in gaussians.items()}
    backend = default_backend(device)
    inside = torch.zeros(len(on_device["means"]), device=device)
    total = torch.zeros_like(inside)
    progress = Progress("removal: faint", len(cameras))
    for k, (camera, region) in enumerate(zip(cameras, regions, strict=True)):
        feature = torch.zeros(len(inside), 2, device=device, requires_grad=True)
        blended = rasterize(on_device, feature, CameraTensors.from_camera(camera, device), backend, depth=False)[0]
        mask = torch.as_tensor(region, dtype=torch.float32, device=device)
        (grad,) = torch.autograd.grad((blended[..., 0] * mask).sum() + blended[..., 1].sum(), feature)
        inside += grad[:, 0]
        total += grad[:, 1]
        progress.update(k + 1)
    progress.close()
    return inside.cpu().numpy(), total.cpu().numpy()


def faint_inside(gaussians: Gaussians, removed: np.ndarray, candidates: np.ndarray, cameras: list[Camera],
                 regions: list[np.ndarray], device: torch.device) -> np.ndarray:
    """(N,) bool over `gaussians`: those not `removed`, among the `candidates` (off the supports and other
    objects), faint, whose weight in the scene without the `removed` ones falls inside the `regions` of the
    `cameras` by INSIDE_SHARE or more."""
    out = np.zeros(len(removed), bool)
    keep = np.flatnonzero(~removed)
    remaining = {k: v[torch.from_numpy(keep)] for k, v in gaussians.items()}
    opacity = torch.sigmoid(remaining["opacities"]).numpy()
    inside, total = rendered_weights(remaining, cameras, regions, device)
    faint = candidates[keep] & (opacity < FAINT_OPACITY) & (total > 0) & (inside >= INSIDE_SHARE * total)
    out[keep[faint]] = True
    return out
