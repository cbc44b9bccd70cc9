"""A pure-torch 3DGS rasterizer with gsplat 1.5.3's math and conventions, for the CPU (gsplat has none).

Mirrors gsplat's `rasterization(..., packed=False)` for pinhole cameras, classic mode: EWA projection with
gsplat's frustum clamp of the Jacobian, a 0.3 px blur added to the 2D covariance, radii of min(3.33,
sqrt(2 ln(255 opacity))) sigma per axis, 16 px tiles, front-to-back compositing with alpha capped at 0.999,
alphas under 1/255 skipped and a pixel finished once transmittance would fall to 1e-4. Pixel centres are at
+0.5. Dense per tile, so it is only meant for small images (tests); agreement with gsplat is checked on
the GPU by benchmarks/rasterizer_agreement.py.

How it is fast enough on a CPU (a tiny training 1.5x or more, a 160x120 view of 73k Gaussians 3.4x against one
blend a tile): each tile is blended in 8 px sub-tiles from the Gaussians of its list that can reach them, the
sub-tiles in batches padded to one list length, one gather of the Gaussians a batch, not one a tile. A Gaussian
left out of a sub-tile, or a padding one, has an alpha of 0 in every pixel there, so that changes nothing; the
falloff as a polynomial rounds differently (a view's loss and gradients agreed to 6-7 digits).
"""

from __future__ import annotations

import math

import torch
import torch.nn.functional as F

ALPHA_THRESHOLD = 1.0 / 255.0
TILE = 16
SUB = 8  # px: each tile is blended in sub-tiles this size, each from the Gaussians in its list that reach it
BATCH = 1 << 21  # (sub-tile x pixel x Gaussian) entries blended at once


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
    ids, counts, corners = _sub_tile_lists(mean2d.detach(), conics.detach(), opacities.detach(), radii, z.detach(),
                                           width, height)
    flat = features.new_zeros(height * width, features.shape[1] + 1)
    if counts:
        # one more Gaussian, of opacity 0, pads the sub-tiles' lists to one length: it draws nothing
        padded = [torch.cat([t, t.new_zeros(1, *t.shape[1:])]) for t in (mean2d, conics, opacities, features)]
        ids = torch.cat([ids, ids.new_full((1,), len(mean2d))])
        lengths, corners = torch.tensor(counts), torch.tensor(corners, dtype=mean2d.dtype)
        starts = lengths.cumsum(0) - lengths
        pieces, pixels = [], []
        for group in _batches(counts):
            group = torch.tensor(group)
            step = torch.arange(int(lengths[group].max()))[None]
            # past its own list a row reads the pad, the last entry of `ids`
            rows = ids[torch.where(step < lengths[group, None], starts[group, None] + step, -1)]
            corner = corners[group]
            blended = _blend(*(t[rows.to(t.device)] for t in padded), corner.to(mean2d.device))
            where, inside = _pixels(corner, width, height)
            pieces.append(blended[inside.to(blended.device)])
            pixels.append(where[inside])
        flat = flat.index_put((torch.cat(pixels).to(flat.device),), torch.cat(pieces))
    # gsplat's 2D means always get a gradient (zero where nothing was drawn); a view this loop drew nothing of would
    # otherwise leave none, and DefaultStrategy reads it after every backward
    flat = flat.reshape(height, width, -1) + 0.0 * means2d.sum()
    out, alpha_out = flat[..., :-1], flat[..., -1:]
    depth = out[..., -1:] / alpha_out.clamp_min(1e-10)
    info = {"means2d": means2d, "radii": radii[None], "width": width, "height": height, "n_cameras": 1,
            "gaussian_ids": None, "depths": z[None]}
    return torch.cat([out[..., :-1], depth], dim=-1), alpha_out, info


def _sub_tile_lists(mean2d: torch.Tensor, conics: torch.Tensor, opacities: torch.Tensor, radii: torch.Tensor,
                    z: torch.Tensor, width: int, height: int) -> tuple[torch.Tensor, list[int], list[tuple[int, int]]]:
    """The SUB px sub-tiles' lists one after another (on the CPU), each list's length and each sub-tile's top-left
    corner (x0, y0), those with none left out. A list holds, front to back, the Gaussians of its 16 px tile's list as
    gsplat makes it (the projected box, `radii`, overlaps the tile) whose alpha can reach 1/255 in the sub-tile
    (_reach). Each Gaussian's sub-tiles are a rectangle, so the lists come from one sort of (sub-tile, Gaussian)
    pairs rather than a pass over every Gaussian for each tile."""
    across, down = math.ceil(width / SUB), math.ceil(height / SUB)
    per_tile = TILE // SUB
    rx, ry = radii[:, 0].float(), radii[:, 1].float()
    low, high = _reach(mean2d, conics, opacities)
    first, last = [], []  # each Gaussian's sub-tile columns, then rows: [first, last)
    for axis, r, size, count in ((0, rx, width, across), (1, ry, height, down)):
        tiles = math.ceil(size / TILE)
        tile0 = torch.floor((mean2d[:, axis] - r) / TILE).clamp(0, tiles)
        tile1 = torch.ceil((mean2d[:, axis] + r) / TILE).clamp(0, tiles)
        first.append(torch.maximum(per_tile * tile0, torch.floor(low[:, axis] / SUB)).clamp(0, count).long())
        last.append(torch.minimum(per_tile * tile1, torch.ceil(high[:, axis] / SUB)).clamp(0, count).long())
    wide, tall = (last[0] - first[0]).clamp_min(0), (last[1] - first[1]).clamp_min(0)
    # stable: a clone shares its parent's depth, and an unstable sort made runs differ (which of the two
    # gets the front's gradient)
    order = torch.argsort(z, stable=True)
    order = order[(radii > 0).any(-1)[order] & (wide * tall > 0)[order]]
    cells = (wide * tall)[order]
    ids = order.repeat_interleave(cells)
    step = torch.arange(len(ids), device=ids.device) - (torch.cumsum(cells, 0) - cells).repeat_interleave(cells)
    column = first[0][ids] + step % wide[ids]
    row = first[1][ids] + torch.div(step, wide[ids], rounding_mode="floor")
    keys, where = torch.sort(row * across + column, stable=True)  # front to back within each sub-tile
    keys, counts = torch.unique_consecutive(keys, return_counts=True)
    return ids[where].cpu(), counts.tolist(), [(k % across * SUB, k // across * SUB) for k in keys.tolist()]


def _reach(mean2d: torch.Tensor, conics: torch.Tensor, opacities: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """(N, 2) low and high corners of the box outside which a Gaussian's alpha is under 1/255 (so blending skips
    it): its ellipse at sqrt(2 ln(255 opacity)) sigma, not clamped at 3.33 sigma as the tile lists' boxes are, with a
    px to spare. Why: a Gaussian in a tile's list that cannot reach a sub-tile adds exactly nothing there, and the
    blend is dense in pixels x Gaussians (a small Gaussian's 16 px tiles hold 4 times the pixels its 8 px ones do)."""
    a, b, c = conics.unbind(-1)
    det = (a * c - b * b).clamp_min(1e-12)  # the conic's inverse is the 2D covariance: (c, -b, a) / det
    extent = torch.sqrt(2.0 * torch.log((opacities * 255.0).clamp_min(1.0)))
    half = extent[:, None] * torch.stack([c / det, a / det], -1).clamp_min(0).sqrt() + 1.0
    return mean2d - half, mean2d + half


def _batches(lengths: list[int]) -> list[list[int]]:
    """The sub-tiles (by their lists' `lengths`) in groups blended at once, each padded to its longest list: longest
    first, a group closed where the next list is under 0.6 of its longest (so padding at most doubles its work) or
    at BATCH entries. Why: one blend per sub-tile is a few dozen small tensor operations, and on a CPU their
    overhead, not the arithmetic, was most of a tiny training step."""
    groups: list[list[int]] = []
    longest = 0
    for k in sorted(range(len(lengths)), key=lambda k: -lengths[k]):
        if groups and lengths[k] >= 0.6 * longest and (len(groups[-1]) + 1) * SUB * SUB * longest <= BATCH:
            groups[-1].append(k)
        else:
            groups.append([k])
            longest = lengths[k]
    return groups


def _pixels(corner: torch.Tensor, width: int, height: int) -> tuple[torch.Tensor, torch.Tensor]:
    """(B, SUB * SUB) each sub-tile's pixels' flat indices into the image, row by row from its `corner` (B, 2),
    and whether each lies inside the image (a sub-tile at its right or bottom edge may reach past it)."""
    y = corner[:, 1, None].long() + torch.arange(SUB).repeat_interleave(SUB)[None]
    x = corner[:, 0, None].long() + torch.arange(SUB).repeat(SUB)[None]
    inside = (x < width) & (y < height)
    return y * width + x, inside


def _blend(mean2d, conics, opacities, features, corner: torch.Tensor) -> torch.Tensor:
    """(B, SUB * SUB, D + 1) B sub-tiles' pixels (row by row from each one's `corner`, (B, 2)) blended front to back
    from their Gaussians ((B, n, ...) 2D means, conics, opacities, features, in depth order), alpha last: alpha capped
    at 0.999, alphas under 1/255 skipped, a pixel finished once its transmittance would fall to 1e-4, as gsplat."""
    offsets = torch.arange(SUB, device=mean2d.device, dtype=mean2d.dtype) + 0.5 - SUB / 2
    v, u = offsets.repeat_interleave(SUB), offsets.repeat(SUB)  # about the sub-tile's centre: the digits stay
    # sigma = 0.5 a dx^2 + 0.5 c dy^2 + b dx dy (dx = mean - pixel) as a polynomial in the pixel's u, v: one matrix
    # product for the batch instead of a dozen (pixels x Gaussians) passes
    a, b, c = conics.unbind(-1)
    centre = corner + SUB / 2
    mx, my = mean2d[..., 0] - centre[:, :1], mean2d[..., 1] - centre[:, 1:]
    powers = torch.stack([u * u, v * v, u * v, u, v, torch.ones_like(u)], -1)
    terms = torch.stack([0.5 * a, 0.5 * c, b, -a * mx - b * my, -c * my - b * mx,
                         0.5 * a * mx * mx + 0.5 * c * my * my + b * mx * my], 1)
    sigma = powers @ terms
    alpha = torch.clamp(opacities[:, None] * torch.exp(-sigma), max=0.999)
    # sigma is a positive form of the pixel's offset; the check keeps gsplat's, past the expansion's rounding
    alpha = torch.where((sigma >= -1e-4) & (alpha >= ALPHA_THRESHOLD), alpha, torch.zeros_like(alpha))
    transmit = torch.cumprod(1 - alpha, dim=-1)
    before = torch.cat([torch.ones_like(transmit[..., :1]), transmit[..., :-1]], dim=-1)
    weights = alpha * before * (transmit > 1e-4)
    return torch.cat([weights @ features, weights.sum(dim=-1, keepdim=True)], dim=-1)
