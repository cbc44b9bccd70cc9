"""A pure-torch 3DGS rasterizer with gsplat 1.5.3's math and conventions, for the CPU (gsplat has none).

Mirrors gsplat's `rasterization(..., packed=False)` for pinhole cameras, classic mode: EWA projection with
gsplat's frustum clamp of the Jacobian, a 0.3 px blur added to the 2D covariance, radii of min(3.33,
sqrt(2 ln(255 opacity))) sigma per axis, 16 px tiles, front-to-back compositing with alpha capped at 0.999,
alphas under 1/255 skipped and a pixel finished once transmittance would fall to 1e-4. Pixel centres are at
+0.5. Dense per tile, so it is only meant for small images (tests); agreement with gsplat is checked on
the GPU by benchmarks/rasterizer_agreement.py.
"""

from __future__ import annotations

import math

import torch
import torch.nn.functional as F

ALPHA_THRESHOLD = 1.0 / 255.0
TILE = 16


def quat_rotations(quats: torch.Tensor) -> torch.Tensor:
    """(N, 3, 3) rotations of quaternions (N, 4) w, x, y, z, normalised as gsplat does; columns are the axes."""
    w, x, y, z = F.normalize(quats, dim=-1).unbind(-1)
    return torch.stack([
        1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
    ], dim=-1).reshape(-1, 3, 3)


def quat_scale_to_covar(quats: torch.Tensor, scales: torch.Tensor) -> torch.Tensor:
    """(N, 3, 3) covariances from quaternions (N, 4) w, x, y, z and (activated) scales (N, 3)."""
    m = quat_rotations(quats) * scales[:, None, :]
    return m @ m.transpose(1, 2)


def project(means, quats, scales, opacities, viewmat, K, width, height, near_plane, far_plane, eps2d):
    """Camera z, 2D means (N, 2), conics (N, 3) and radii (N, 2) int32 (0 = culled), as gsplat projects."""
    R, t = viewmat[:3, :3], viewmat[:3, 3]
    mean_c = means @ R.T + t
    x, y, z = mean_c.unbind(-1)
    in_depth = (z >= near_plane) & (z <= far_plane)
    zs = torch.where(in_depth, z, torch.ones_like(z))  # keeps culled Gaussians finite
    fx, fy, cx, cy = K[0, 0], K[1, 1], K[0, 2], K[1, 2]
    tan_fovx, tan_fovy = 0.5 * width / fx, 0.5 * height / fy
    tx = zs * torch.clamp(x / zs, -(cx / fx + 0.3 * tan_fovx), (width - cx) / fx + 0.3 * tan_fovx)
    ty = zs * torch.clamp(y / zs, -(cy / fy + 0.3 * tan_fovy), (height - cy) / fy + 0.3 * tan_fovy)
    zero = torch.zeros_like(zs)
    J = torch.stack([fx / zs, zero, -fx * tx / zs**2, zero, fy / zs, -fy * ty / zs**2], -1).reshape(-1, 2, 3)
    cov2d = J @ (R @ quat_scale_to_covar(quats, scales) @ R.T) @ J.transpose(1, 2)
    a, b, c = cov2d[:, 0, 0] + eps2d, cov2d[:, 0, 1], cov2d[:, 1, 1] + eps2d
    det = a * c - b * b
    safe_det = torch.where(det > 0, det, torch.ones_like(det))
    conics = torch.stack([c / safe_det, -b / safe_det, a / safe_det], -1)
    mean2d = torch.stack([fx * x / zs + cx, fy * y / zs + cy], -1)
    opaque = opacities >= ALPHA_THRESHOLD
    extend = torch.clamp(torch.sqrt(2.0 * torch.log(opacities.clamp_min(ALPHA_THRESHOLD) / ALPHA_THRESHOLD)),
                         max=3.33)
    rx, ry = torch.ceil(extend * a.clamp_min(0).sqrt()), torch.ceil(extend * c.clamp_min(0).sqrt())
    mx, my = mean2d.detach().unbind(-1)
    on_screen = (mx + rx > 0) & (mx - rx < width) & (my + ry > 0) & (my - ry < height)
    valid = in_depth & (det > 0) & opaque & ((rx > 0) | (ry > 0)) & on_screen
    radii = torch.stack([rx, ry], -1).detach().to(torch.int32) * valid[:, None]
    return z, mean2d, conics, radii


def rasterize_reference(means, quats, scales, opacities, colors, viewmat, K, width: int, height: int,
                        near_plane: float = 0.01, far_plane: float = 1e10, eps2d: float = 0.3):
    """Render (H, W, D + 1) colours with expected depth last, alpha (H, W, 1), and gsplat-style info.

    Inputs as gsplat's: means (N, 3), quats (N, 4), scales (N, 3) and opacities (N,) activated,
    colors (N, D), viewmat (4, 4) world-to-camera, K (3, 3).
    """
    z, mean2d, conics, radii = project(means, quats, scales, opacities, viewmat, K, width, height,
                                       near_plane, far_plane, eps2d)
    means2d = mean2d[None]  # the strategy reads this tensor's gradient
    mean2d = means2d[0]
    features = torch.cat([colors, z[:, None]], dim=-1)
    out = features.new_zeros(height, width, features.shape[1])
    alpha_out = features.new_zeros(height, width)
    tiles_x, tiles_y = math.ceil(width / TILE), math.ceil(height / TILE)
    mx, my = mean2d.detach().unbind(-1)
    rx, ry = radii[:, 0].float(), radii[:, 1].float()
    tx0 = torch.floor((mx - rx) / TILE).clamp(0, tiles_x)
    tx1 = torch.ceil((mx + rx) / TILE).clamp(0, tiles_x)
    ty0 = torch.floor((my - ry) / TILE).clamp(0, tiles_y)
    ty1 = torch.ceil((my + ry) / TILE).clamp(0, tiles_y)
    valid = (radii > 0).any(-1)
    # stable: a clone shares its parent's depth, and an unstable sort made runs differ (which of the two
    # gets the front's gradient)
    order = torch.argsort(z.detach(), stable=True)
    for ty in range(tiles_y):
        for tx in range(tiles_x):
            hit = valid & (tx0 <= tx) & (tx < tx1) & (ty0 <= ty) & (ty < ty1)
            ids = order[hit[order]]
            if ids.numel() == 0:
                continue
            y0, x0 = ty * TILE, tx * TILE
            y1, x1 = min(y0 + TILE, height), min(x0 + TILE, width)
            py, px = torch.meshgrid(torch.arange(y0, y1, device=means.device) + 0.5,
                                    torch.arange(x0, x1, device=means.device) + 0.5, indexing="ij")
            dx = mean2d[ids, 0][None] - px.reshape(-1, 1)
            dy = mean2d[ids, 1][None] - py.reshape(-1, 1)
            con = conics[ids]
            sigma = 0.5 * (con[:, 0] * dx * dx + con[:, 2] * dy * dy) + con[:, 1] * dx * dy
            alpha = torch.clamp(opacities[ids][None] * torch.exp(-sigma), max=0.999)
            alpha = torch.where((sigma >= 0) & (alpha >= ALPHA_THRESHOLD), alpha, torch.zeros_like(alpha))
            transmit = torch.cumprod(1 - alpha, dim=1)
            before = torch.cat([torch.ones_like(transmit[:, :1]), transmit[:, :-1]], dim=1)
            weights = alpha * before * (transmit > 1e-4)
            out[y0:y1, x0:x1] = (weights @ features[ids]).reshape(y1 - y0, x1 - x0, -1)
            alpha_out[y0:y1, x0:x1] = weights.sum(dim=1).reshape(y1 - y0, x1 - x0)
    # gsplat's 2D means always get a gradient (zero where nothing was drawn); a view this loop drew nothing of would
    # otherwise leave none, and DefaultStrategy reads it after every backward
    out = out + 0.0 * means2d.sum()
    alpha_out = alpha_out[..., None]
    depth = out[..., -1:] / alpha_out.clamp_min(1e-10)
    info = {"means2d": means2d, "radii": radii[None], "width": width, "height": height, "n_cameras": 1,
            "gaussian_ids": None, "depths": z[None]}
    return torch.cat([out[..., :-1], depth], dim=-1), alpha_out, info
