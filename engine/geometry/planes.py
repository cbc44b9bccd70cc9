"""Planes among 3D points: level ones (floor, table top), given the scene's up direction, which the hole masks'
support (engine.edit.support_plane) and the object proposals (engine.segment.proposals) both stand on; and
those of any other orientation (a wall, a shelf's back), which objects hang on or are mounted to."""

from __future__ import annotations

import numpy as np

MAX_TILT_DEG = 20  # how far a level plane's normal may lean from the scene's up
MAX_POINTS = 20_000  # RANSAC counts inliers among at most this many points
MIN_INLIER_SHARE = 0.3
AREA = 3.0  # a level plane's points spread at least this many tol across both of its directions (is_area)
THIN = 0.45  # a plane holds at least this share of the points within 3 tol of it within tol (a slice through a
# solid or a wall holds a third: measured on real captures, where vertical slices of a statue and horizontal
# slices of a wall were taken for planes before; a noisy table top three bands thick holds 0.57)


def is_thin(points: np.ndarray, normal: np.ndarray, offset: float, tol: float) -> bool:
    """Whether the points near the plane lie on it rather than pass through it (see THIN)."""
    distance = np.abs(points @ normal + offset)
    return (distance < tol).sum() >= THIN * max((distance < 3 * tol).sum(), 1)


def is_area(points: np.ndarray, tol: float) -> bool:
    """Whether points near a plane spread over an area of it and not along a strip: the second largest standard
    deviation at least AREA tol. A level slab through a wall holds a strip of it (the tiny wall-mounted run's top
    edge of the wall, 112 Gaussians: 0.30 by 0.02, 1.2 tol) that is as long and as thin as a floor; the tiny
    livingroom's floor and table top spread 0.47 and 0.26 (17 and 10 tol)."""
    if len(points) < 3:
        return False
    deviations = np.linalg.svd(points - points.mean(0), compute_uv=False) / np.sqrt(len(points))
    return bool(deviations[1] >= AREA * tol)


def fit_plane(points: np.ndarray, tol: float, seed: int = 0, tries: int = 300, up: np.ndarray | None = None,
              min_share: float = MIN_INLIER_SHARE) -> tuple[np.ndarray, float] | None:
    """RANSAC plane (unit normal n, offset d with n.p + d = 0) within `tol` of at least `min_share` of
    `points`, refitted by least squares to its inliers, or None. With `up`, only planes within MAX_TILT_DEG
    of level, their normals pointing up."""
    if len(points) < 50:
        return None
    rng = np.random.default_rng(seed)
    if len(points) > MAX_POINTS:
        points = points[rng.choice(len(points), MAX_POINTS, replace=False)]
    a, b, c = (points[rng.integers(0, len(points), tries)] for _ in range(3))
    normals = np.cross(b - a, c - a)
    norms = np.linalg.norm(normals, axis=1)
    keep = norms > 1e-12
    normals, a = normals[keep] / norms[keep, None], a[keep]
    if up is not None:
        normals *= np.where(normals @ up < 0, -1.0, 1.0)[:, None]
        level = normals @ up > np.cos(np.radians(MAX_TILT_DEG))
        normals, a = normals[level], a[level]
    if not len(normals):
        return None
    offsets = -np.einsum("ij,ij->i", normals, a)
    counts = np.zeros(len(normals), np.int64)
    for lo in range(0, len(normals), 64):  # 64 candidates at a time: 20k x 64 distances
        counts[lo:lo + 64] = (np.abs(points @ normals[lo:lo + 64].T + offsets[lo:lo + 64]) < tol).sum(0)
    best = int(np.argmax(counts))
    if counts[best] < max(min_share * len(points), 3):
        return None
    inliers = points[np.abs(points @ normals[best] + offsets[best]) < tol]
    mean = inliers.mean(0)
    normal = np.linalg.svd(inliers - mean, full_matrices=False)[2][-1]
    normal = normal if normal @ normals[best] > 0 else -normal
    return normal, float(-normal @ mean)


def level_normal(points: np.ndarray, up: np.ndarray, tol: float) -> np.ndarray:
    """The normal of the fullest level plane among `points` (the floor, a table top), or `up` if none: the
    scene's level, more exact than the cameras' up (SfM's is only roughly up) and shared by every plane
    resting parallel to it.

    The fullest level slab may be no plane at all: in a scene that is mostly wall (a trophy mounted on it, the
    floor barely in view) it is a strip across the wall, whose refit normal leans anywhere about the strip (24
    degrees from up on a tiny wall-mounted run; the level 'planes' then cut through the trophy and left nothing
    of it free). So the fit counts only when its refit normal is still level and the points lie on it rather
    than pass through it (is_thin)."""
    plane = fit_plane(points, tol, up=up, min_share=0.0)
    if plane is None:
        return up
    normal, offset = plane
    level = normal @ up >= np.cos(np.radians(MAX_TILT_DEG))
    return normal if level and is_thin(points, normal, offset, tol) else up


def support_planes(points: np.ndarray, up: np.ndarray, tol: float, share: float, min_radius: float = 0.0,
                   most: int = 4, normal: np.ndarray | None = None) -> list[tuple[np.ndarray, float]]:
    """Level planes (unit normal n, offset d, n.p + d = 0) that hold at least `share` of `points` within
    `tol` and spread at least `min_radius` around their centre, by the median distance (a large round
    object's horizontal slice holds many points too, but is no wider than the object; a few floaters at
    the same height far away must not make it wide). Fullest first.

    All share one normal: `normal` if given, else the level of these points (level_normal). Along it the
    planes are layers of heights, taken one at a time where the most points lie within tol, each one's
    points leaving before the next. Fitting each plane's own normal instead tilted one through two layers
    a few mm apart (the tabletop's mat and the tiles beside it: 2-3.5 mm below the mat under the toy, and
    the holes' IoU 0.57; docs/BENCHMARKS.md)."""
    need = max(share * len(points), 3)
    if len(points) < need:
        return []
    normal = level_normal(points, up, tol) if normal is None else normal
    heights = points @ normal
    left, planes = np.ones(len(points), bool), []
    for _ in range(4 * most):
        if len(planes) == most or left.sum() < need:
            break
        ordered = np.sort(heights[left])
        lo, hi = np.percentile(ordered, [0.5, 99.5])
        steps = np.arange(lo, hi + tol, tol / 2)
        within = np.searchsorted(ordered, steps + tol) - np.searchsorted(ordered, steps - tol)
        k = int(np.argmax(within))
        if within[k] < need:
            break
        seed = left & (np.abs(heights - steps[k]) < tol)
        centre = float(np.median(heights[seed]))
        on = left & (np.abs(heights - centre) < tol)
        held = points[on]
        spread = np.median(np.linalg.norm(held - held.mean(0), axis=1))
        if (on.sum() >= need and spread >= min_radius and is_thin(points[left], normal, -centre, tol)
                and is_area(held, tol) and not any(abs(centre + d) < 2 * tol for _, d in planes)):
            planes.append((normal, -centre))
        left &= ~(on | seed)
    return planes


def tilted_planes(points: np.ndarray, up: np.ndarray, tol: float, share: float, min_radius: float, most: int = 3,
                  seed: int = 0) -> list[tuple[np.ndarray, float]]:
    """Planes that are not level (their normal more than MAX_TILT_DEG from `up`: walls, slopes), each holding
    at least `share` of `points` within `tol` and spread at least `min_radius` around its centre; fullest
    first, each one's points leaving before the next is looked for."""
    need = max(share * len(points), 50)
    left, planes = np.ones(len(points), bool), []
    for k in range(2 * most):
        if len(planes) == most or left.sum() < need:
            break
        plane = fit_plane(points[left], tol, seed=seed + k, tries=600, min_share=need / max(left.sum(), 1))
        if plane is None:
            break
        normal, offset = plane
        on = left & (np.abs(points @ normal + offset) < tol)
        held = points[on]
        spread = np.median(np.linalg.norm(held - held.mean(0), axis=1)) if len(held) else 0.0
        if (abs(normal @ up) < np.cos(np.radians(MAX_TILT_DEG)) and spread >= min_radius
                and is_thin(points[left], normal, offset, tol)):
            planes.append((normal, offset))
        left &= ~on
    return planes
