"""Object proposals from a trained scene's geometry alone, for a capture without masks (`segment --auto`).

What a capture's cameras tell: what they look at (the point nearest every optical axis), how far away it is
(the orbit radius R, the scene's scale whatever SfM chose) and which way is up (their mean up vector).
Objects are what rests on a support surface there or hangs on one: the dense horizontal planes (floor, table
top, slab) are found from the Gaussians' heights and refined by least squares, then the dense planes of other
orientations (walls) by RANSAC, so that an object mounted on a wall comes apart from it; the solid Gaussians
off those planes, above
the lowest one and within the orbit, are split into objects by 3D connectivity on a voxel grid (voxel
`voxel` x R, or their median spacing where the reconstruction is sparser); pieces as wide as the orbit
(walls, the table's rim) stay background. A piece is that wide also where a sparse or short reconstruction
leaves a table top as a noisy slab rather than a plane, whose Gaussians off the plane's band link every object
on it: a wide piece is split again `peel` times, each time without its Gaussians within one more `plane_tol`
of a plane, and what comes off is kept where it rests on a plane. Faint Gaussians (floaters, soft edges) and
those peeled off join the object of the nearest solid one left within two voxels. Every length is a fraction
of R, so the same defaults hold for a generated scene in metres and an SfM frame of arbitrary scale.
"""

from __future__ import annotations

import numpy as np
import torch

from engine.base.knn import knn
from engine.geometry.scene_geometry import (
    Frame,
    ProposalConfig,
    Supports,
    components,
    plane_heights,
    spacing,
    voxel_components,
)


def merge_stacked(points: np.ndarray, voxel: np.ndarray, label: np.ndarray, up: np.ndarray, gap: float
                  ) -> np.ndarray:
    """Per voxel, its component after joining pieces stacked on one another (a statue's body on its plinth,
    split where the reconstruction is thin): one lies wholly above the other, at most `gap` higher, and
    their footprints overlap by half of the smaller one. Pieces side by side (objects on a table) stay apart."""
    part = label[voxel]
    ids = np.unique(part)
    height = points @ up
    flat = points - np.outer(height, up)
    basis = np.linalg.svd(np.eye(3) - np.outer(up, up))[0][:, :2]  # two horizontal axes
    xy = flat @ basis
    stats = {}
    for k in ids:
        sel = part == k
        stats[k] = (height[sel].min(), height[sel].max(), xy[sel].min(0), xy[sel].max(0))
    a, b = [], []
    for i in ids:
        for j in ids:
            lo_i, hi_i, min_i, max_i = stats[i]
            lo_j, hi_j, min_j, max_j = stats[j]
            if not (lo_j > lo_i and hi_j > hi_i and abs(lo_j - hi_i) <= gap):  # j rests on i
                continue
            overlap = np.prod(np.clip(np.minimum(max_i, max_j) - np.maximum(min_i, min_j), 0, None))
            smaller = min(np.prod(max_i - min_i), np.prod(max_j - min_j))
            if smaller > 0 and overlap >= 0.5 * smaller:
                a.append(i)
                b.append(j)
    if not a:
        return label
    joined = components(len(label), np.array(a), np.array(b))
    return joined[label]


def propose(means: np.ndarray, opacity: np.ndarray, frame: Frame, support: Supports, config: ProposalConfig
            ) -> tuple[np.ndarray, dict]:
    """(N,) proposal id per Gaussian (0 = background, ids in no order) and what was found, given the orbit's
    frame and the supports `find_supports` found in it."""
    r = frame.radius
    planes, walls, near = support.planes, support.walls, support.near
    solid = near & (opacity >= config.solid)
    tol = config.plane_tol * r
    heights = plane_heights(means, planes)
    candidate = support.free
    ids = np.zeros(len(means), np.int64)
    seeds = np.flatnonzero(candidate & solid)
    if len(seeds) == 0:
        return ids, {"planes": len(planes), "walls": len(walls), "proposals": 0, "radius": r}
    size = max(config.voxel * r, spacing(means[seeds]))  # a sparse reconstruction needs coarser voxels
    bands = [tol * (1 + k) for k in range(config.peel + 1)] if planes else [tol]
    ids[seeds], peeled = split_pieces(means[seeds], heights[seeds], bands, size, config.stack_gap * size,
                                      frame.up, config.max_width * r)
    anchors = seeds[~peeled]
    joining = np.concatenate([np.flatnonzero(candidate & ~solid), seeds[peeled]])
    if len(joining) and len(anchors):  # each joins the object of the nearest anchor, if near
        near_anchor, nearest = knn(torch.as_tensor(means[joining]), torch.as_tensor(means[anchors]), 1)
        close = (near_anchor[:, 0] <= 2 * size).numpy()
        ids[joining[close]] = ids[anchors][nearest[close, 0].numpy()]
    levels = sorted(round(float(-d - frame.center @ n) / r, 3) for n, d in planes)
    return ids, {"planes": len(planes), "walls": len(walls), "plane_heights": levels, "radius": round(r, 4),
                 "voxel": round(size, 5),
                 "proposals": int(len(np.unique(ids)) - (ids == 0).any())}


def split_pieces(points: np.ndarray, heights: np.ndarray, bands: list[float], size: float, min_gap: float,
                 up: np.ndarray, max_width: float) -> tuple[np.ndarray, np.ndarray]:
    """Per point, its piece (0 = background; ids in no order) and whether a wider band peeled it off.
    Pieces are connected on a voxel grid of `size`, stacked ones joined (a length `min_gap` or 2.5 bands
    apart, whichever is more), and kept when no wider than `max_width`. Wider ones are split again without
    their points nearer a plane than the next of `bands` (`heights`: each point's signed height above each
    plane), and what that splits off is kept only where it rests on a plane (its lowest point at most the band
    and two voxels above one), so a table top's underside and rim stay scenery; what is left after the last
    band is background."""
    distance = np.abs(heights).min(1) if heights.shape[1] else np.full(len(points), np.inf)
    ids = np.zeros(len(points), np.int64)
    peeled = np.zeros(len(points), bool)
    todo = np.arange(len(points))
    for step, band in enumerate(bands):
        if step:
            peeled[todo[distance[todo] < band]] = True
            todo = todo[distance[todo] >= band]
        if not len(todo):
            break
        voxel, label = voxel_components(points[todo], size)
        gap = max(min_gap, 2.5 * band)  # what a plane's band may have cut out of an object
        part = merge_stacked(points[todo], voxel, label, up, gap)[voxel]
        keep = _component_widths(points[todo], part, up) <= max_width
        if step:
            keep &= _resting(heights[todo], part, band + 2 * size)
        ids[todo[keep[part]]] = ids.max() + 1 + part[keep[part]]
        todo = todo[~keep[part]]
    return ids, peeled


def _resting(heights: np.ndarray, part: np.ndarray, reach: float) -> np.ndarray:
    """Per component label (indexed by label), whether its lowest point lies 0 to `reach` above some plane."""
    low = np.full((part.max() + 1, heights.shape[1]), np.inf)
    np.minimum.at(low, part, heights)
    return ((low >= 0) & (low <= reach)).any(1)


def _component_widths(points: np.ndarray, label: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Per component label (indexed by label), the horizontal diagonal of its points' extent."""
    flat = points - np.outer(points @ up, up)
    width = np.zeros(label.max() + 1)
    for axis in range(3):
        lo = np.full(label.max() + 1, np.inf)
        hi = np.full(label.max() + 1, -np.inf)
        np.minimum.at(lo, label, flat[:, axis])
        np.maximum.at(hi, label, flat[:, axis])
        width += np.where(np.isfinite(lo), hi - lo, 0.0) ** 2
    return np.sqrt(width)
