"""Level planes (floor, table top) among 3D points, given the scene's up direction: what the hole masks'
support (engine.edit.support_plane) and the object proposals (engine.train.proposals) both stand on."""

from __future__ import annotations

import numpy as np

COARSE = 5  # level planes are first looked for in height bins this many tolerances wide


def support_planes(points: np.ndarray, up: np.ndarray, tol: float, share: float, min_radius: float = 0.0,
                   most: int = 4) -> list[tuple[np.ndarray, float]]:
    """Horizontal planes (unit normal n, offset d, n.p + d = 0) that hold at least `share` of `points`
    within `tol` and spread at least `min_radius` around their centre, by the median distance (a large
    round object's horizontal slice holds many points too, but is no wider than the object; a few floaters
    at the same height far away must not make it wide). SfM's up is only roughly up, which
    smears a wide floor over many heights: peaks are looked for in bins of COARSE x tol, then each normal
    is refitted by least squares to a band narrowing to tol."""
    heights = points @ up
    lo, hi = np.percentile(heights, [0.5, 99.5]) if len(points) else (0.0, 0.0)
    counts, edges = np.histogram(heights, bins=max(int((hi - lo) / (COARSE * tol)), 1), range=(lo, hi))
    planes: list[tuple[np.ndarray, float]] = []
    for b in np.argsort(-counts):
        if counts[b] < share * len(points) or len(planes) == most:
            break
        normal, offset = up, -0.5 * (edges[b] + edges[b + 1])
        for width in (COARSE * tol, 2 * tol, tol, tol):
            band = points[np.abs(points @ normal + offset) < width]
            if len(band) < 3:
                break
            mean = band.mean(0)
            normal = np.linalg.svd(band - mean, full_matrices=False)[2][-1]
            normal = normal if normal @ up > 0 else -normal
            offset = float(-normal @ mean)
        held = points[np.abs(points @ normal + offset) < tol]
        seen = any(abs(offset - d) < COARSE * tol for _, d in planes)
        spread = np.median(np.linalg.norm(held - held.mean(0), axis=1)) if len(held) else 0.0
        if (normal @ up > np.cos(np.radians(20)) and len(held) >= share * len(points) and not seen
                and spread >= min_radius):
            planes.append((normal, offset))
    return planes
