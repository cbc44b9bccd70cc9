"""Render Gaussians for one camera: RGB, expected depth, alpha and the 16-channel identity map, in one pass.

gsplat 1.5.3 on CUDA; on the CPU the pure-torch reference (engine.rasterize_reference) with the same math.
RGB (from spherical harmonics, evaluated here for both back ends) and identity are blended together as
19 channels, with expected depth appended ("RGB+ED"), so one rasterization gives everything training needs.
"""

from __future__ import annotations

from dataclasses import dataclass

import torch

from engine.camera import Camera
from engine.gaussians import Gaussians
from engine.rasterize_reference import rasterize_reference
from engine.sh import eval_sh

NEAR_PLANE, FAR_PLANE, EPS2D = 0.01, 1e10, 0.3


@dataclass
class RenderOutput:
    rgb: torch.Tensor  # (H, W, 3) linear in [0, 1] as trained (the images' sRGB values)
    depth: torch.Tensor  # (H, W) expected z-depth, sum(w z) / sum(w)
    alpha: torch.Tensor  # (H, W) accumulated opacity
    identity: torch.Tensor  # (H, W, 16) blended identity encoding
    info: dict  # projection data for densification strategies (means2d, radii, width, height, ...)


@dataclass(frozen=True)
class CameraTensors:
    """A camera on a device: world-to-camera (4, 4), intrinsics (3, 3), centre (3,), size."""

    viewmat: torch.Tensor
    K: torch.Tensor
    center: torch.Tensor
    width: int
    height: int

    @classmethod
    def from_camera(cls, camera: Camera, device: torch.device | str) -> CameraTensors:
        def tensor(a):
            return torch.as_tensor(a, dtype=torch.float32, device=device)

        return cls(tensor(camera.world_to_camera), tensor(camera.K), tensor(camera.center), camera.width,
                   camera.height)


def default_backend(device: torch.device | str) -> str:
    return "gsplat" if torch.device(device).type == "cuda" else "reference"


def render(gaussians: Gaussians, camera: CameraTensors, sh_degree: int, backend: str | None = None) -> RenderOutput:
    """Render `gaussians` (see engine.gaussians) seen by `camera`, using SH bands up to `sh_degree`."""
    means = gaussians["means"]
    backend = backend or default_backend(means.device)
    dirs = torch.nn.functional.normalize(means.detach() - camera.center, dim=-1)
    rgb = torch.clamp_min(eval_sh(sh_degree, gaussians["sh0"], gaussians["shN"], dirs) + 0.5, 0.0)
    features = torch.cat([rgb, gaussians["identity"]], dim=-1)
    args = (means, gaussians["quats"], torch.exp(gaussians["scales"]), torch.sigmoid(gaussians["opacities"]),
            features)
    if backend == "gsplat":
        from gsplat import rasterization

        colors, alphas, info = rasterization(*args, camera.viewmat[None], camera.K[None], camera.width,
                                             camera.height, near_plane=NEAR_PLANE, far_plane=FAR_PLANE,
                                             eps2d=EPS2D, sh_degree=None, packed=False, render_mode="RGB+ED")
        colors, alphas = colors[0], alphas[0]
    else:
        colors, alphas, info = rasterize_reference(*args, camera.viewmat, camera.K, camera.width, camera.height,
                                                   NEAR_PLANE, FAR_PLANE, EPS2D)
    return RenderOutput(rgb=colors[..., :3], depth=colors[..., -1], alpha=alphas[..., 0],
                        identity=colors[..., 3:-1], info=info)
