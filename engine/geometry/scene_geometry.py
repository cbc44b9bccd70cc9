"""The geometry that finding objects (`segment`) and removing them (`remove`, `clean`) share: where a capture's
cameras look (its frame), connected pieces on a voxel grid, the support planes objects stand on or hang from,
and the Gaussians' spacing. Every length is a fraction of the orbit radius R, so the same defaults hold for a
generated scene in metres and an SfM frame of arbitrary scale."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from engine.base.knn import knn
from engine.formats.cameras import Camera, mean_up
from engine.geometry.planes import support_planes, tilted_planes

WALL_STRIP = 0.5  # a level plane whose points lie this much on walls is a strip across them (strip_of_walls)
SLICED = 0.5  # a wall whose solid Gaussians lie this much on one object is that object sliced (unsliced)
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
    code = voxel_codes(keys)
    order = np.argsort(code)
    a, b = [], []
    for offset in NEIGHBOURS:
        other = voxel_codes(keys + offset)
        at = np.clip(np.searchsorted(code[order], other), 0, len(code) - 1)
        hit = code[order][at] == other
        a.append(np.flatnonzero(hit))
        b.append(order[at[hit]])
    label = components(len(keys), np.concatenate(a), np.concatenate(b))
    return voxel.ravel(), label


def voxel_codes(keys: np.ndarray) -> np.ndarray:
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
    on_level = level_band(means, planes, tol)
    walls = tilted_planes(means[solid & ~on_level], frame.up, tol, config.plane_share, config.plane_radius * r)
    planes = [plane for plane in planes if not strip_of_walls(means[solid], plane, walls, tol)]
    return Supports(planes, walls, near, free_of(means, near, planes, walls, tol))


def free_of(means: np.ndarray, near: np.ndarray, planes: list[tuple[np.ndarray, float]],
            walls: list[tuple[np.ndarray, float]], tol: float) -> np.ndarray:
    """(N,) bool: within the orbit (`near`), off every plane and wall (by `tol`) and above the lowest level plane,
    measured along the planes' own normal (support_planes gives them one), not the cameras' `up`: SfM's up is only
    roughly up, and 10 degrees off it moves a point 0.8 R out from the centre by 7 tol."""
    heights = plane_heights(means, planes + walls)
    free = near & (np.abs(heights) >= tol).all(1)
    if planes:
        free &= heights[:, :len(planes)].max(1) > tol  # the lowest plane's height is the largest of them
    return free


def unsliced(supports: Supports, means: np.ndarray, solid: np.ndarray, member: np.ndarray, tol: float
             ) -> Supports:
    """The `supports` without the walls that slice an object: a tilted plane whose `solid` Gaussians within the
    orbit (and within `tol` of it) lie mostly (SLICED) on `member` (the Gaussians voted salient, or those a removal
    takes). Why: a thin figure holds a plane as well as a wall does. On the shared statue capture a vertical plane
    through the bronze figure (a voxel or two thick) was taken for a wall, 91% of its solid Gaussians voted salient;
    the figure was then not free of the supports, and `segment --auto` took its legs and left its chest and head
    standing. A wall behind a mounted trophy holds the trophy's plaque, a small share of it."""
    on = [solid & supports.near & (np.abs(plane_heights(means, [wall])[:, 0]) < tol) for wall in supports.walls]
    kept = [wall for wall, held in zip(supports.walls, on, strict=True) if member[held].sum() <= SLICED * held.sum()]
    if len(kept) == len(supports.walls):
        return supports
    return Supports(supports.planes, kept, supports.near, free_of(means, supports.near, supports.planes, kept, tol))


def strip_of_walls(points: np.ndarray, plane: tuple[np.ndarray, float], walls: list[tuple[np.ndarray, float]],
                   tol: float) -> bool:
    """Whether a level `plane`'s points (those of `points` within `tol`) lie mostly (WALL_STRIP) on the `walls`:
    then it is a level slab across a wall, not a floor. On a wall-mounted run at 160x120 two such slabs (78-86% of
    their points on the wall, the rest the trophy's head) were taken for floors at the trophy's height and cut it
    in three; a floor meets its wall along one edge only."""
    on = np.abs(plane_heights(points, [plane])[:, 0]) < tol
    if not walls or not on.any():
        return False
    return bool((np.abs(plane_heights(points[on], walls)) < tol).any(1).mean() >= WALL_STRIP)


def plane_heights(points: np.ndarray, planes: list[tuple[np.ndarray, float]]) -> np.ndarray:
    """(N, P) each point's signed height above each plane (normals point up)."""
    return np.stack([points @ n + d for n, d in planes], axis=1) if planes else np.zeros((len(points), 0))


def level_band(points: np.ndarray, planes: list[tuple[np.ndarray, float]], tol: float) -> np.ndarray:
    """(N,) bool: the points within `tol` of any of the level `planes` (a floor's or a table's band)."""
    return (np.abs(plane_heights(points, planes)) < tol).any(1)


def spacing(points: np.ndarray, sample: int = 2000) -> float:
    """Median distance from a point to its nearest neighbour (on a sample): a sparse reconstruction (few
    views, few steps) needs voxels at least this large to hold one object together."""
    if len(points) < 2:
        return 0.0
    rng = np.random.default_rng(0)
    queries = points[rng.choice(len(points), min(sample, len(points)), replace=False)]
    distances = knn(torch.as_tensor(queries), torch.as_tensor(points), 2)[0][:, 1]  # [:, 0] is the point itself
    return float(distances.median())
