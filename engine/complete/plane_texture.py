"""The hole's part on the support plane filled once, in the plane's own texture, and carried into every view by
the plane's homography (3DTexMOR's idea: a hole on a plane inpainted in the plane's rectified texture).

Why: an inpainter in a view sees the plane foreshortened and only that view's border of the hole; the same
plane seen straight on, with the colours of every view that saw each point (the median, so one view's seam or
highlight drops out), is an undistorted picture with the whole border around the unseen patch. Filled there
once, every view that sees the patch gets the same colour at the same point by construction, with no depth
estimate involved (a plane point's place in a view is exact; Ref's carry places texture by inpainted depth).

The grid is square, centred on the object's footprint, GRID_REACH footprint radii across each way, its cells
the size of a pixel of the nearest view (at most MAX_CELLS a side). A cell's colour is the median over the
views (at most MAX_VIEWS, spread evenly) that see it: in frame, in front, not in the view's (dilated) hole, and
with the view's depth at that pixel on the plane within `rel_tol` (nothing in front of it, the plane's edge
not passed). The cells no view sees and that some view's hole needs are inpainted, the rest are context.
A view's hole pixel takes the texture where its ray meets the plane inside the grid, at a filled or seen
cell, and its own inpainted depth puts the surface there (within `rel_tol`); other hole pixels keep what
they had (Ref's carried fill).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from engine.edit.plane_grid import PlaneFrame
from engine.edit.support_plane import Footprint, plane_along_rays
from engine.formats.cameras import Camera, project, sample_nearest
from engine.io.masks import dilate

GRID_REACH = 2.5  # the grid reaches this many footprint radii from its centre, each way
MAX_CELLS = 512  # cells a side at most (a 512 x 512 texture: 0.1-0.3 s to inpaint with telea)
MAX_VIEWS = 24  # views gathered into the texture, evenly spread
EDGE_PX = 2  # px of each view's hole border left out of the texture (a render's edge blur)
REL_TOL = 0.03  # a view's depth within this share of the plane point's depth shows the plane there


@dataclass(frozen=True)
class TextureGrid:
    """Square cells on the plane: cell (i, j) is centred at origin + (j + 0.5) a + (i + 0.5) b, in the frame's
    in-plane axes, on the plane."""

    frame: PlaneFrame
    origin: np.ndarray  # (2,) in-plane coordinates of the grid's corner
    cell: float
    size: int

    def centres(self) -> np.ndarray:
        """(size * size, 3) world points of the cells' centres, row by row."""
        steps = (np.arange(self.size) + 0.5) * self.cell
        jj, ii = np.meshgrid(steps + self.origin[0], steps + self.origin[1])
        return self.frame.point(np.stack([jj.reshape(-1), ii.reshape(-1)], axis=1))

    @property
    def plane(self) -> tuple[np.ndarray, float]:
        """The plane as (unit normal, offset), n.p + d = 0."""
        return self.frame.n, self.frame.d

    def coords(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N,) column and row coordinates (cell units, centres at k + 0.5) of world points on the plane."""
        return ((points @ self.frame.a - self.origin[0]) / self.cell,
                (points @ self.frame.b - self.origin[1]) / self.cell)


def texture_grid(plane: tuple[np.ndarray, float], footprint: Footprint, cameras: list[Camera]) -> TextureGrid:
    """The grid around the footprint, cells a pixel of the nearest view across (MAX_CELLS a side at most)."""
    frame = PlaneFrame.of(np.asarray(plane[0], float), float(plane[1]))
    centre = footprint.centre - (footprint.centre @ frame.n + frame.d) * frame.n
    half = GRID_REACH * footprint.radius
    depth = min(float(project(c, centre[None])[2][0]) for c in cameras)
    pixel = max(depth, 1e-6) / max(min(c.fx, c.fy) for c in cameras)
    cell = max(pixel, 2 * half / MAX_CELLS)
    size = int(np.ceil(2 * half / cell))
    return TextureGrid(frame, np.array([centre @ frame.a - half, centre @ frame.b - half]), cell, size)


def gather(grid: TextureGrid, cameras: list[Camera], images: list[np.ndarray], holes: list[np.ndarray],
           depths: list[np.ndarray], rel_tol: float = REL_TOL) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(texture (S, S, 3) uint8, seen (S, S) bool, needed (S, S) bool): each cell's median colour over the views
    that see it outside their holes, whether any does, and whether it lies in some view's hole on the plane."""
    points = grid.centres()
    picks = np.linspace(0, len(cameras) - 1, min(len(cameras), MAX_VIEWS)).round().astype(int)
    samples = np.full((len(picks), len(points), 3), np.nan, np.float32)
    needed = np.zeros(len(points), bool)
    for k, i in enumerate(picks):
        u, v, z = project(cameras[i], points)
        surface, inside = sample_nearest(depths[i], u, v)
        on_plane = inside & (z > 0) & np.isfinite(surface) & (np.abs(surface - z) <= rel_tol * z)
        in_hole, _ = sample_nearest(dilate(holes[i], EDGE_PX), u, v)
        in_own_hole, _ = sample_nearest(holes[i], u, v)
        needed |= inside & (z > 0) & in_own_hole
        seen = on_plane & ~in_hole
        colour, _ = sample_nearest(images[i], u, v)
        samples[k, seen] = colour[seen]
    seen_any = ~np.isnan(samples[..., 0]).all(axis=0)
    texture = np.zeros((len(points), 3), np.uint8)
    if seen_any.any():
        texture[seen_any] = np.round(np.nanmedian(samples[:, seen_any], axis=0)).astype(np.uint8)
    shape = (grid.size, grid.size)
    return texture.reshape(*shape, 3), seen_any.reshape(shape), (needed & ~seen_any).reshape(shape)


def apply_texture(grid: TextureGrid, texture: np.ndarray, valid: np.ndarray, camera: Camera, hole: np.ndarray,
                  depth: np.ndarray, image: np.ndarray, rel_tol: float = REL_TOL) -> tuple[np.ndarray, np.ndarray]:
    """`image` with each `hole` pixel whose ray meets the plane on a `valid` cell, where its own (inpainted)
    `depth` puts the surface on the plane, read from the texture (bilinear); and the (H, W) mask of those."""
    from engine.complete.reference_fill import sample_bilinear

    ys, xs = np.nonzero(hole)
    unit, z_plane = plane_along_rays(camera, ys, xs, grid.plane)
    with np.errstate(invalid="ignore"):
        on_plane = (z_plane > 0) & np.isfinite(depth[ys, xs]) & (np.abs(depth[ys, xs] - z_plane) <= rel_tol * z_plane)
    cols, rows = grid.coords(camera.center + unit * np.where(on_plane, z_plane, 0.0)[:, None])
    cell_ok, inside = sample_nearest(valid, cols, rows)
    use = on_plane & inside & cell_ok
    out, placed = image.copy(), np.zeros(hole.shape, bool)
    if use.any():
        out[ys[use], xs[use]] = np.round(sample_bilinear(texture.astype(np.float32), cols[use] - 0.5,
                                                         rows[use] - 0.5)).astype(image.dtype)
        placed[ys[use], xs[use]] = True
    return out, placed


def fill_texture(texture: np.ndarray, seen: np.ndarray, needed: np.ndarray, inpainter) -> np.ndarray:
    """The texture with its `needed` cells inpainted once (by the inpainting's own inpainter). Cells neither
    seen nor needed (past the plane's edge, behind other things) first take the nearest seen cell's colour, so
    the inpainter never reads them as black."""
    if not seen.any():
        return texture
    _, labels = cv2.distanceTransformWithLabels((~seen).astype(np.uint8), cv2.DIST_L2, 5,
                                                labelType=cv2.DIST_LABEL_PIXEL)
    extended = texture[seen][labels - 1]  # labels number the seen cells in row-major order, from 1
    return inpainter.inpaint(extended, needed, "rgb", None) if needed.any() else extended


def write_plane_texture(images: list[np.ndarray], cameras: list[Camera], holes: list[np.ndarray],
                        depths: list[np.ndarray], plane: tuple[np.ndarray, float], footprint: Footprint,
                        inpainter) -> tuple[list[np.ndarray], dict, np.ndarray]:
    """Every view's `images` with the on-plane part of its hole read from the plane's texture (inpainted once),
    a report, and the texture. `depths` are the views' inpainted depths (the removed scene's outside the holes)."""
    grid = texture_grid(plane, footprint, cameras)
    texture, seen, needed = gather(grid, cameras, images, holes, depths)
    filled = fill_texture(texture, seen, needed, inpainter)
    valid, out, placed = seen | needed, [], 0
    for camera, hole, depth, image in zip(cameras, holes, depths, images, strict=True):
        image, landed = apply_texture(grid, filled, valid, camera, hole, depth, image)
        out.append(image)
        placed += int(landed.sum())
    total = int(sum(h.sum() for h in holes))
    return out, {"cells": grid.size, "cell": round(grid.cell, 6), "seen_cells": int(seen.sum()),
                 "filled_cells": int(needed.sum()), "placed_px": placed, "hole_px": total,
                 "placed_share": round(placed / total, 4) if total else None}, filled
