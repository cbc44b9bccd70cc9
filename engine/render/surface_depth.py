"""The depth of the surface a pixel shows: where its accumulated opacity passes one half.

3DGS's expected depth (sum w z / sum w) averages everything a pixel blends. A trained surface is partly
see-through: on a 30k-step livingroom run the table top's own Gaussians give 50-65% of its pixels' opacity,
and the table's underside, the floor and the backdrop behind supply the rest, so table points lifted with
expected depth land 4 cm (median) below the top, more towards the image's edges (docs/BENCHMARKS.md).
Hole masks compare depths to 1%; they need the surface itself.

gsplat 1.5.3 renders no median depth for 3D Gaussians, so it comes from one more rasterization with 2K
channels: the view's Gaussians are put in K depth bins of equal counts (narrow where surfaces are dense),
and each blends its weight and weight * z into its bin's two channels. Blending runs front to back, so a
prefix sum over the bins is the opacity in front of each bin's far edge; the surface lies in the bin where
that passes 1/2, at that bin's own weighted mean depth (nothing behind the bin counts). Both back ends
share the code (engine.render.rasterize).
"""

from __future__ import annotations

import torch

from engine.io.gaussians import Gaussians
from engine.render.rasterize import NEAR_PLANE, CameraTensors, rasterize

BINS = 64
SURFACE_ALPHA = 0.5  # also where a pixel starts to count as showing a surface at all


def depth_bins(z: torch.Tensor, in_view: torch.Tensor, bins: int = BINS) -> torch.Tensor:
    """(N,) bin index 0..bins-1 of each camera depth `z`, edges at equal counts of the `in_view` ones."""
    ordered = torch.sort(z[in_view]).values.contiguous()
    if ordered.numel() == 0:
        return torch.zeros_like(z, dtype=torch.long)
    picks = torch.linspace(0, ordered.numel() - 1, bins + 1, device=z.device)[1:-1].round().long()
    return torch.bucketize(z.contiguous(), ordered[picks].contiguous(), right=True)


@torch.no_grad()
def surface_depth(gaussians: Gaussians, camera: CameraTensors, backend: str, level: float = SURFACE_ALPHA
                  ) -> tuple[torch.Tensor, torch.Tensor]:
    """(H, W) z-depth where each pixel's accumulated opacity passes `level` (the surface it shows at the default;
    inf where its opacity stays below `level`, or below 1/2 for a lower one) and (H, W) alpha."""
    means = gaussians["means"]
    cam = means @ camera.viewmat[:3, :3].T + camera.viewmat[:3, 3]
    z = cam[:, 2]
    u = camera.K[0, 0] * cam[:, 0] / z.clamp_min(NEAR_PLANE) + camera.K[0, 2]
    v = camera.K[1, 1] * cam[:, 1] / z.clamp_min(NEAR_PLANE) + camera.K[1, 2]
    in_view = (z > NEAR_PLANE) & (u > -0.5 * camera.width) & (u < 1.5 * camera.width) \
        & (v > -0.5 * camera.height) & (v < 1.5 * camera.height)
    one_hot = torch.nn.functional.one_hot(depth_bins(z, in_view), BINS).to(means.dtype)
    blended, alpha, _ = rasterize(gaussians, torch.cat([one_hot, one_hot * z[:, None]], dim=-1), camera,
                                  backend, depth=False)
    weight, weighted_z = blended[..., :BINS], blended[..., BINS:]
    surface_bin = (weight.cumsum(-1) < level).sum(-1, keepdim=True).clamp_max(BINS - 1)
    depth = (weighted_z.gather(-1, surface_bin) / weight.gather(-1, surface_bin).clamp_min(1e-10))[..., 0]
    alpha = alpha[..., 0]
    return torch.where(alpha >= max(level, SURFACE_ALPHA), depth, torch.full_like(depth, float("inf"))), alpha
