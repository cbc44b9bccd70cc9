"""No Gaussian may hold a camera: those whose 1-sigma core contains a training camera's centre are emptied.

Why: splatting projects a Gaussian by its centre (EWA's linearisation there). One that surrounds the camera
is culled from the views that have its centre behind them and drawn over the whole picture in the views that
have it in front: on the skull capture (dark room, black background) a few such Gaussians, scene-sized
(scales 2-10 against an orbit of radius 3.4), at opacity up to 0.99, stood 1.1-1.3 from the cameras and covered
whole test views in one flat dark colour (test views at 6-11 dB beside others at 16-21; CPU at 1/8 size with a
random background: 10.5 and 10.9 dB). MCMC removes nothing by size, and nothing else clears them.

No surface stands where the photographer's camera stood, so a Gaussian whose core holds a camera (its density
there at least 61% of its peak) is a floater by construction; emptied (its opacity set far below any strategy's
floor), MCMC relocates it onto a live one and DefaultStrategy prunes it at the next refinement, and the training
goes on to cover what it drew with Gaussians that project correctly. Only the training cameras are used: the test
views' poses play no part.

How deep (`train --camera-clearance S`; test PSNR on an H200, docs/BENCHMARKS.md "Real captures"): the statue capture
19.23 / 20.54 / 20.36 dB at 1 / 2 / 3 sigma, the skull 17.02 / 19.56 / 21.22: the captures' floaters reach past the
core, so the default preset clears FULL_SIGMAS (3; its density there 1% of the peak). The tiny CPU preset keeps the
core: at 2 sigma (58a97ca) and at 3 (a04844c's parent) the small runs that `make demo` and the tests train (128 px,
20k Gaussians, DefaultStrategy) lost their walls: wall Gaussians 0.4-0.7 wide stood 1.0-1.35 from the cameras
(1.9-3 sigma), were emptied again and again while the photos grew them back (1.6 dB lost at 3 sigma), and at 2 sigma
four tests failed: segmentation found one object where the livingroom has several, none on the wall. At the
generated families' full size (320x240, 300k budget; H200, 557c660) 3 sigma lost nothing: livingroom 39.53 -> 39.98,
wallmount 44.21 -> 44.24 dB; the captures at 557c660: skull 21.17, statue 19.85 (docs/BENCHMARKS.md "Real captures").
"""

from __future__ import annotations

import numpy as np
import torch

from engine.render.rasterize_reference import quat_rotations

SIGMAS = 1.0  # a camera inside the core: the density there at least exp(-1/2) of the peak
FULL_SIGMAS = 3.0  # the default preset's depth: the density there at least exp(-9/2), 1% of the peak
EMPTY_LOGIT = -12.0  # sigmoid: 6e-6, below MCMC's relocation floor and DefaultStrategy's pruning one (0.005)
CHUNK = 65_536  # Gaussians tested at once (memory: CHUNK x cameras x 3)


def centres_of(cameras, device: torch.device | str = "cpu") -> torch.Tensor:
    """(C, 3) float32 the centres of `cameras` (engine.formats.cameras.Camera), (0, 3) for none."""
    centres = np.asarray([camera.center for camera in cameras], dtype=np.float32).reshape(-1, 3)
    return torch.as_tensor(centres, device=device)


def holding_cameras(means: torch.Tensor, quats: torch.Tensor, log_scales: torch.Tensor, centres: torch.Tensor,
                    sigmas: float = SIGMAS) -> torch.Tensor:
    """(N,) bool: the Gaussians whose `sigmas` ellipsoid contains one of the camera `centres` (C, 3)."""
    return cameras_held(means, quats, log_scales, centres, sigmas).any(-1)


def cameras_held(means: torch.Tensor, quats: torch.Tensor, log_scales: torch.Tensor, centres: torch.Tensor,
                 sigmas: float = SIGMAS) -> torch.Tensor:
    """(N, C) bool: whether Gaussian n's `sigmas` ellipsoid contains camera centre c (C, 3)."""
    held = torch.zeros(len(means), len(centres), dtype=torch.bool, device=means.device)
    centres = centres.to(means)
    for start in range(0, len(means), CHUNK):
        part = slice(start, start + CHUNK)
        axes = quat_rotations(quats[part])  # (n, 3, 3): columns are the Gaussian's axes
        offsets = centres[None] - means[part, None]  # (n, C, 3)
        local = torch.einsum("nij,nci->ncj", axes, offsets) / torch.exp(log_scales[part])[:, None]
        held[part] = local.square().sum(-1) < sigmas * sigmas
    return held


@torch.no_grad()
def empty_camera_holders(params, centres: torch.Tensor, sigmas: float = SIGMAS) -> torch.Tensor:
    """Set the opacity of every Gaussian in `params` that holds a camera (at `sigmas`) to EMPTY_LOGIT; how many
    there were, as a tensor on the parameters' device (read at the end of a run: no wait on the GPU each time)."""
    held = holding_cameras(params["means"], params["quats"], params["scales"], centres, sigmas)
    opacities = params["opacities"].data
    opacities.masked_fill_(held.reshape(opacities.shape), EMPTY_LOGIT)
    return held.sum()


@torch.no_grad()
def holders_of(gaussians, centres: torch.Tensor, floor: float = 0.005, sigmas: float = SIGMAS) -> list[int]:
    """Per camera centre (C, 3), how many Gaussians above opacity `floor` hold it: the test views' count says
    whether what covers a test view is such a Gaussian (one the training views' clearance cannot see), without
    changing the scene."""
    live = torch.sigmoid(gaussians["opacities"].flatten()) > floor
    held = cameras_held(gaussians["means"], gaussians["quats"], gaussians["scales"], centres, sigmas)
    return (held & live[:, None]).sum(0).tolist()
