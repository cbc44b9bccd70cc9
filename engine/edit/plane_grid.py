"""The support plane as a frame and a grid of cells over it around the object: where the effects of an
object on its support (its cast shadow, the darkening under and beside it) are found and relit."""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
import torch

from engine.base.knn import knn_distances
from engine.render.rasterize_reference import quat_scale_to_covar


@dataclass
class PlaneFrame:
    """The support plane as a frame: unit normal n (up), in-plane axes a and b, offset d (n.p + d = 0)."""

    n: np.ndarray
    a: np.ndarray
    b: np.ndarray
    d: float

    @classmethod
    def of(cls, n: np.ndarray, d: float) -> PlaneFrame:
        a = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        a /= np.linalg.norm(a)
        return cls(n=n, a=a, b=np.cross(n, a), d=float(d))

    def height(self, p: np.ndarray) -> np.ndarray:
        return p @ self.n + self.d

    def cast(self, p: np.ndarray, light: np.ndarray) -> np.ndarray:
        """(N, 2) in-plane coordinates where the light's rays through `p` meet the plane."""
        on_plane = p - (self.height(p) / (light @ self.n))[:, None] * light[None]
        return np.stack([on_plane @ self.a, on_plane @ self.b], axis=1)

    def flat(self, p: np.ndarray) -> np.ndarray:
        """(N, 2) in-plane coordinates straight below `p`."""
        return np.stack([p @ self.a, p @ self.b], axis=1)

    def point(self, flat: np.ndarray) -> np.ndarray:
        """(N, 3) world points on the plane at in-plane coordinates `flat` (N, 2): `flat`'s inverse there."""
        return flat[:, :1] * self.a + flat[:, 1:] * self.b - self.d * self.n

    def light(self, elevation: float, azimuth: float) -> np.ndarray:
        el, az = math.radians(elevation), math.radians(azimuth)
        return math.cos(el) * (math.cos(az) * self.a + math.sin(az) * self.b) + math.sin(el) * self.n


@dataclass(frozen=True)
class PlaneGrid:
    """A square grid of cells over the plane around the object, for casting footprints."""

    origin: np.ndarray
    cell: float
    size: int

    def index(self, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N, 2) cell indices of in-plane points and (N,) whether each falls on the grid."""
        ij = np.floor((flat - self.origin) / self.cell).astype(int)
        return ij, (ij >= 0).all(1) & (ij < self.size).all(1)

    def raster(self, flat: np.ndarray, spacing: float = 0.0) -> np.ndarray:
        """(size, size) bool occupancy of in-plane points, gaps closed up to the `spacing` of the points they
        came from (surface_spacing) and at least one cell: a sparse object (a few hundred Gaussians on a CPU
        test scene, 2-4 cells apart) otherwise casts a shadow of scattered cells that misses much of the real
        one. Not stretched along a low light's cast, where its points lie farther apart: solid long casts then
        won the light search on a checkered floor (dark squares as dark as the threshold), 20 degrees for 40."""
        ij, ok = self.index(flat)
        occupied = np.zeros((self.size, self.size), np.uint8)
        occupied[ij[ok, 0], ij[ok, 1]] = 1
        width = 2 * math.ceil(spacing / self.cell / 2) + 1
        kernel = (np.ones((3, 3), np.uint8) if width <= 3
                  else cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (width, width)))
        return cv2.morphologyEx(occupied, cv2.MORPH_CLOSE, kernel) > 0

    def cells(self, occupied: np.ndarray, flat: np.ndarray) -> np.ndarray:
        """(N,) values of the grid `occupied` (bool or any per-cell array) at in-plane points; zero off it."""
        ij, ok = self.index(flat)
        values = np.zeros((len(flat), *occupied.shape[2:]), dtype=occupied.dtype)
        values[ok] = occupied[ij[ok, 0], ij[ok, 1]]
        return values

    def shadowed(self, frame: PlaneFrame, light: np.ndarray, obj: np.ndarray, points: np.ndarray,
                 spacing: float = 0.0) -> np.ndarray:
        """(N,) bool: which `points` lie in the shadow of the `obj` points (`spacing` apart) cast by `light`."""
        return self.cells(self.raster(frame.cast(obj, light), spacing), frame.cast(points, light))


def grown(cells: np.ndarray, n: int) -> np.ndarray:
    """(size, size) bool: the grid's `cells` grown by `n` cells each way, a square (the grid's own neighbourhood)."""
    return cv2.dilate(cells.astype(np.uint8), np.ones((2 * n + 1, 2 * n + 1), np.uint8)) > 0


def pooled_sums(size: int, ij: np.ndarray, values: np.ndarray, use: np.ndarray, width: int
                ) -> tuple[np.ndarray, np.ndarray]:
    """(size, size, C) sums of the `values` (M, C) of the samples in cells `ij` that `use`, over a window `width`
    cells wide around each cell, and (size, size) how many samples each window holds."""
    sums = np.zeros((size, size, values.shape[1]), np.float64)
    counts = np.zeros((size, size), np.float64)
    np.add.at(sums, (ij[use, 0], ij[use, 1]), values[use])
    np.add.at(counts, (ij[use, 0], ij[use, 1]), 1.0)
    box = (width, width)
    sums = np.stack([cv2.boxFilter(sums[..., c], -1, box, normalize=False, borderType=cv2.BORDER_CONSTANT)
                     for c in range(values.shape[1])], -1)
    return sums, cv2.boxFilter(counts, -1, box, normalize=False, borderType=cv2.BORDER_CONSTANT)


def surface_spacing(points: np.ndarray, most: int = 6000) -> float:
    """How far apart neighbouring `points` of a sampled surface lie: the 90th percentile of their
    nearest-neighbour distances, the widest gap a raster of them should close. Of more than `most` points a
    random `most` are measured and the result scaled by sqrt(most / N), as spacing on a surface goes with
    1 / sqrt(density)."""
    if len(points) < 2:
        return 0.0
    pick = np.random.default_rng(0).choice(len(points), most, replace=False) if len(points) > most else slice(None)
    nearest = knn_distances(torch.as_tensor(points[pick], dtype=torch.float32), 1)[:, 0].numpy()
    return float(np.percentile(nearest, 90)) * math.sqrt(min(1.0, most / len(points)))


@dataclass(frozen=True)
class Site:
    """Where the object stood: the plane's frame, the object's height, its centre and radius across the plane,
    how far around it its effects are looked for, and the grid over that."""

    frame: PlaneFrame
    size: float
    centre: np.ndarray
    radius: float
    reach: float
    grid: PlaneGrid
    spacing: float  # between the object's neighbouring points (surface_spacing): gaps its rasters close

    @classmethod
    def of(cls, obj: np.ndarray, plane: tuple[np.ndarray, float]) -> Site:
        """For the object's core Gaussians' centres `obj` standing on `plane`; the reach is the shadow of a
        light 18 degrees above the plane."""
        frame = PlaneFrame.of(*plane)
        heights = frame.height(obj)
        size = float(np.percentile(heights, 98) - np.percentile(heights, 2))
        flat = frame.flat(obj)
        centre = np.median(flat, axis=0)
        radius = float(np.percentile(np.linalg.norm(flat - centre, axis=1), 95))
        reach = radius + 3.0 * size
        cell = radius / 12
        grid = PlaneGrid(centre - reach, cell, int(math.ceil(2 * reach / cell)) + 1)
        return cls(frame=frame, size=size, centre=centre, radius=radius, reach=reach, grid=grid,
                   spacing=surface_spacing(obj))

    def near_plane(self, points: np.ndarray, below: float, extent: np.ndarray | None = None) -> np.ndarray:
        """(N,) bool: within reach across the plane, from `below` x the object's height under it to 5% above;
        with `extent` (N,), how far each point's Gaussian reaches up (2 sigma along the normal), a Gaussian
        below the band counts when it reaches into it: a few views trained for a few hundred steps draw the
        support with large Gaussians centred well under it (tiny CPU statue: 23% of the opacity drawing the
        true shadow lay below the band, effect recall 0.41 on one seed, 0.67 with their extent)."""
        h, across = self.frame.height(points), self.frame.flat(points)
        top = h if extent is None else h + extent
        return ((np.linalg.norm(across - self.centre, axis=1) < self.reach) & (top > -below * self.size)
                & (h < 0.05 * self.size))

    def reach_up(self, gaussians) -> np.ndarray:
        """(N,) how far each Gaussian reaches along the plane's normal: 2 sigma (its covariance along n)."""
        covar = quat_scale_to_covar(gaussians["quats"], torch.exp(gaussians["scales"])).double().numpy()
        n = self.frame.n
        return 2.0 * np.sqrt(np.maximum(np.einsum("i,nij,j->n", n, covar, n), 0.0))
