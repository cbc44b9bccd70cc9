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

from dataclasses import dataclass

import numpy as np
import torch

from engine.base.knn import knn
from engine.formats.cameras import Camera, mean_up
from engine.io.planes import support_planes, tilted_planes

NEIGHBOURS = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)
                       if (i, j, k) > (0, 0, 0)])  # half of the 26-neighbourhood: each pair of voxels once


@dataclass
class ProposalConfig:
    solid: float = 0.2  # opacity a Gaussian needs to shape the geometry
    plane_tol: float = 0.02  # a Gaussian within this x R of a support plane belongs to it
    plane_share: float = 0.05  # a plane holds at least this share of the solid Gaussians in the orbit
    plane_radius: float = 0.15  # ... spread at least this x R around its centre (median distance)
    voxel: float = 0.02  # connectivity voxel, x R (at least the Gaussians' median spacing)
    stack_gap: float = 2.0  # a piece resting this many voxels above another's footprint is part of it
    max_width: float = 0.8  # a piece wider than this x R is scenery, not an object
    orbit: float = 1.0  # objects lie within this x R of the look-at point, horizontally
    peel: int = 2  # a piece wider than max_width is split again this often, the planes' band wider each time


@dataclass
class Frame:
    """Where a capture's cameras look, how far they are and which way is up."""

    center: np.ndarray
    radius: float
    up: np.ndarray


def camera_frame(cameras: list[Camera]) -> Frame:
    """The point nearest all optical axes (least squares), the median camera distance to it, the mean up."""
    centres = np.stack([c.center for c in cameras])
    axes = np.stack([c.R[2] for c in cameras])  # viewing directions in the world
    projector = np.eye(3)[None] - axes[:, :, None] * axes[:, None, :]
    center = np.linalg.lstsq(projector.sum(0), np.einsum("kij,kj->i", projector, centres), rcond=None)[0]
    up = mean_up(np.stack([c.R for c in cameras]))
    return Frame(center, float(np.median(np.linalg.norm(centres - center, axis=1))),
                 np.array([0.0, 0.0, 1.0]) if up is None else up)


def components(count: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Connected components of `count` nodes joined by edges (a, b): the smallest node of each, per node
    (min-label hooking with pointer jumping: a few dozen vectorised passes, no graph library)."""
    label = np.arange(count)
    while True:
        new = label.copy()
        low = np.minimum(label[a], label[b])
        np.minimum.at(new, label[a], low)
        np.minimum.at(new, label[b], low)
        while not np.array_equal(new[new], new):
            new = new[new]
        if np.array_equal(new, label):
            return label
        label = new


def voxel_components(points: np.ndarray, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Per point, its occupied voxel's index; per voxel, its component (neighbouring voxels connect)."""
    cells = np.floor(points / size).astype(np.int64)
    keys, voxel = np.unique(cells, axis=0, return_inverse=True)
    code = _codes(keys)
    order = np.argsort(code)
    a, b = [], []
    for offset in NEIGHBOURS:
        other = _codes(keys + offset)
        at = np.clip(np.searchsorted(code[order], other), 0, len(code) - 1)
        hit = code[order][at] == other
        a.append(np.flatnonzero(hit))
        b.append(order[at[hit]])
    label = components(len(keys), np.concatenate(a), np.concatenate(b))
    return voxel.ravel(), label


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


def _codes(keys: np.ndarray) -> np.ndarray:
    shifted = keys + (1 << 20)
    return (shifted[:, 0] << 42) | (shifted[:, 1] << 21) | shifted[:, 2]


@dataclass
class Supports:
    """What objects stand on or hang from: level planes and tilted ones (walls), and per Gaussian whether it
    lies within the orbit (`near`) and is free of them (`free`: near, off every plane, above the lowest level
    one)."""

    planes: list[tuple[np.ndarray, float]]
    walls: list[tuple[np.ndarray, float]]
    near: np.ndarray
    free: np.ndarray


def find_supports(means: np.ndarray, opacity: np.ndarray, frame: Frame, config: ProposalConfig) -> Supports:
    r, tol = frame.radius, config.plane_tol * frame.radius
    offset = means - frame.center
    horizontal = np.linalg.norm(offset - np.outer(offset @ frame.up, frame.up), axis=1)
    near = horizontal <= config.orbit * r
    solid = near & (opacity >= config.solid)
    planes = support_planes(means[solid], frame.up, tol, config.plane_share, config.plane_radius * r)
    on_level = (np.abs(_plane_heights(means, planes)) < tol).any(1)
    walls = tilted_planes(means[solid & ~on_level], frame.up, tol, config.plane_share, config.plane_radius * r)
    free = near & ~on_level & (np.abs(_plane_heights(means, walls)) >= tol).all(1)
    if planes:
        free &= means @ frame.up > min(-d for _, d in planes) + tol
    return Supports(planes, walls, near, free)


def propose(means: np.ndarray, opacity: np.ndarray, frame: Frame, support: Supports, config: ProposalConfig
            ) -> tuple[np.ndarray, dict]:
    """(N,) proposal id per Gaussian (0 = background, ids in no order) and what was found, given the orbit's
    frame and the supports `find_supports` found in it."""
    r = frame.radius
    planes, walls, near = support.planes, support.walls, support.near
    solid = near & (opacity >= config.solid)
    tol = config.plane_tol * r
    heights = _plane_heights(means, planes)
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


def _plane_heights(points: np.ndarray, planes: list[tuple[np.ndarray, float]]) -> np.ndarray:
    """(N, P) each point's signed height above each plane (normals point up)."""
    return np.stack([points @ n + d for n, d in planes], axis=1) if planes else np.zeros((len(points), 0))


def spacing(points: np.ndarray, sample: int = 2000) -> float:
    """Median distance from a point to its nearest neighbour (on a sample): a sparse reconstruction (few
    views, few steps) needs voxels at least this large to hold one object together."""
    if len(points) < 2:
        return 0.0
    rng = np.random.default_rng(0)
    queries = points[rng.choice(len(points), min(sample, len(points)), replace=False)]
    distances = knn(torch.as_tensor(queries), torch.as_tensor(points), 2)[0][:, 1]  # [:, 0] is the point itself
    return float(distances.median())


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
