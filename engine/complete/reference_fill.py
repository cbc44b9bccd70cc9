"""One fill for every view: the hole inpainted once, in a reference view, and carried to the others by depth.

Inpainting each view on its own gives neighbouring views different fills, and a scene trained on them
averages those into blur (AuraFusion360 and 3DTexMOR fill once and reproject; the benchmark paper's
Init inpaints per view). Here the reference is the training view whose fill the others agree with most
(`reference_view`); its hole pixels are lifted with its own inpainted depth and splatted (the nearest wins)
into every other training view's hole, so every view places the one fill at the same 3D points. What it
carries is the consensus (`consensus_fill`): each of its hole pixels the median of every view's own fill of that
point, so the fill keeps what the inpaintings agree on, which makes Init's scene better than any one of them. A view's
own inpainted depth only vetoes a point far from it (`rel_tol`: an occluder the reference filled in front
of the surface this view shows); pixels no point lands on keep their own view's fill. Colours outside the
holes are untouched.

The first version lifted each view's hole pixels with that view's own inpainted depth and looked the colour
up in the reference where the two depths agreed to 3%: two inpainters' depth fills of one surface seldom
agree that well, so it carried 22-27% of the hole pixels with the exemplar inpainter, and placed texture by
a depth that differs from view to view.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

import cv2
import numpy as np

from engine.edit.support_plane import Footprint
from engine.formats.cameras import Camera, backproject, project
from engine.formats.layout import HolesLayout, InpaintedLayout, SceneLayout
from engine.io.image_io import exr_name, read_depth, read_png, write_png
from engine.io.masks import dilate

MAX_JUDGES = 24  # views choosing the reference: 24 x 23 carries, 0.4-0.8 s at 320x240 (all 43: 1.4-2.4 s, same picks)
GAP_PX = 2  # splat gaps closed, px: a view seeing the surface up to 2x larger than the reference (more: own fill)
ROW = 4096  # points per row of a remap grid (cv2.remap's maps stay under 32767 px a side)
BIG = 3.0e38  # float32 stand-in for 'no surface' in the gap closing
MAX_THREADS = 16  # carries at once (each_view)
T, R = TypeVar("T"), TypeVar("R")
REL_TOL = 0.1  # a point this far from the view's own depth fill is something else (two fills of one surface
# differ by a few per cent; an occluder in front of it by far more)


@dataclass
class PlaneFill:
    """What the plane texture needs (engine.complete.plane_texture): the support plane and footprint `remove`
    found, and the inpainting's own inpainter."""

    plane: tuple[np.ndarray, float]
    footprint: Footprint
    inpainter: object


@dataclass
class ViewFill:
    """One training view's own fill: its camera, hole, inpainted image and inpainted depth."""

    camera: Camera
    hole: np.ndarray
    image: np.ndarray
    depth: np.ndarray


def reference_view(fills: dict[int, ViewFill]) -> int:
    """The view whose fill, carried to the others, changes their own fills least, among those that carry
    at least half as many pixels as the best: the fill the views agree on, not an outlier of one view's
    border. (Measured on test views against gt/, PSNR in the true hole: the largest hole, this module's
    first rule, gave 16.0 and 15.8 dB on a statue with Telea and exemplar, this 18.0 and 20.4, the views'
    own fills 17.6 and 19.5; on a livingroom whose holes are 3% of the object, 11.4/11.9 against 11.1/11.0,
    own 11.5/11.3.)"""
    if len(fills) == 1:
        return next(iter(fills))
    views = list(fills)  # candidates and judges: at most MAX_JUDGES, evenly spread (cost grows with their square)
    views = [views[k] for k in np.linspace(0, len(views) - 1, min(len(views), MAX_JUDGES)).round().astype(int)]
    scores = dict(zip(views, each_view(lambda r: _judged(fills, r, views), views), strict=True))
    most = max(carried for _, carried in scores.values())
    return min((r for r, (_, carried) in scores.items() if carried >= most / 2), key=lambda r: scores[r][0])


def _judged(fills: dict[int, ViewFill], r: int, judges: list[int]) -> tuple[float, int]:
    """Reference `r`'s fill carried to each judge: the mean squared change to the judges' own fills, and the
    pixels it reached."""
    ref, squared, carried, pixels = fills[r], 0.0, 0, 0
    for i in judges:
        view = fills[i]
        if i != r:
            out, landed = carry_fill(view.camera, view.hole, view.depth, view.image, ref.camera, ref.hole,
                                     ref.depth, ref.image)
            squared += float(((out.astype(np.float64) - view.image) ** 2)[view.hole].sum())
            carried, pixels = carried + int(landed.sum()), pixels + int(view.hole.sum())
    return squared / max(pixels, 1), carried


def each_view(work: Callable[[T], R], items: list[T]) -> list[R]:
    """`work` on each of `items` in threads, results in order. Why: every carry is a few dozen passes of numpy
    over a hole's pixels, which release the GIL, and a reference's choice takes 24 x 23 of them; one at a time they
    took most of the skull capture's 67 s of the training scene (66 photos at 1424 px, 079d852)."""
    with ThreadPoolExecutor(min(os.cpu_count() or 1, MAX_THREADS)) as pool:
        return list(pool.map(work, items))


def carry_fill(camera: Camera, hole: np.ndarray, depth: np.ndarray, image: np.ndarray, ref: Camera,
               ref_hole: np.ndarray, ref_depth: np.ndarray, ref_image: np.ndarray, rel_tol: float = REL_TOL
               ) -> tuple[np.ndarray, np.ndarray]:
    """`image` with its `hole` pixels replaced by the reference's fill (`ref_hole` pixels at `ref_depth`)
    wherever a splatted point lands within `rel_tol` of this view's own `depth`, and the (H, W) mask of those.

    The splat places the reference's surface (`carried_surface`); the colour of each such pixel is then read
    back from `ref_image` where that surface lies there, bilinearly. (Splatting the colours themselves, the
    first way, left every pixel the splat missed with this view's own fill: a speckle of two fills that cost
    0.01-0.2 of m-SSIM in the hole, measured in docs/BENCHMARKS.md.)"""
    surface = carried_surface(camera, hole, depth, ref, ref_hole, ref_depth, rel_tol)
    rows, cols = np.nonzero(np.isfinite(surface))
    u, v, _ = project(ref, backproject(camera, cols + 0.5, rows + 0.5, surface[rows, cols]))
    inside = (u >= 0.5) & (u <= ref.width - 0.5) & (v >= 0.5) & (v <= ref.height - 0.5)
    rows, cols, u, v = rows[inside], cols[inside], u[inside], v[inside]
    out, carried = image.copy(), np.zeros(hole.shape, bool)
    if len(rows):
        out[rows, cols] = sample_bilinear(ref_image, u - 0.5, v - 0.5).astype(image.dtype)
        carried[rows, cols] = True
    return out, carried


def sample_bilinear(image: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """`image` (H, W[, C]) read bilinearly at the pixel coordinates (x, y), edges replicated: (N[, C]).

    cv2.remap does it, but its maps are an image whose sides must stay under 32767 px: a point list laid out
    as one row crashed on a real capture's hole of 50,000 pixels, so the points are laid out in rows of
    `ROW` here, whatever their number."""
    count = len(x)
    rows = -(-count // ROW)
    grid = np.zeros((2, rows * ROW), np.float32)
    grid[0, :count], grid[1, :count] = x, y
    read = cv2.remap(image, grid[0].reshape(rows, ROW), grid[1].reshape(rows, ROW), cv2.INTER_LINEAR,
                     borderMode=cv2.BORDER_REPLICATE)
    return read.reshape(rows * ROW, *image.shape[2:])[:count]


def consensus_fill(fills: dict[int, ViewFill], r: int) -> np.ndarray:
    """The reference's image with each hole pixel the median of every view's own fill of that point (each
    view's fill carried into the reference by `carry_fill`, the reference's own counted once), per channel.

    One view's fill is one draw of the inpainter; Init trains on all of them and its scene settles near what
    they share, which is closer to the truth than any one draw. The median keeps that, drops the draws that
    pasted something else (a patch of table on a mat), and still gives every view the same fill at the same
    3D points. In 2D on the 640x480 scenes' exact data (exemplar, 10 views) it beat
    the reference's own fill carried on all six scenes in m-PSNR (+0.04 to +1.6 dB) and m-SSIM, and the mean
    on all six in m-SSIM (m-PSNR on four)."""
    ref = fills[r]
    ys, xs = np.nonzero(ref.hole)

    def carried_from(view: ViewFill) -> np.ndarray:
        out, carried = carry_fill(ref.camera, ref.hole, ref.depth, ref.image, view.camera, view.hole, view.depth,
                                  view.image)
        sample = out[ys, xs].astype(np.float32)
        sample[~carried[ys, xs]] = np.nan
        return sample

    samples = [ref.image[ys, xs].astype(np.float32)] + each_view(carried_from, [v for i, v in fills.items() if i != r])
    image = ref.image.copy()
    image[ys, xs] = np.round(np.nanmedian(np.stack(samples), axis=0)).astype(image.dtype)
    return image


def carried_surface(camera: Camera, hole: np.ndarray, depth: np.ndarray, ref: Camera, ref_hole: np.ndarray,
                    ref_depth: np.ndarray, rel_tol: float = REL_TOL) -> np.ndarray:
    """(H, W) z-depth of the reference's filled surface in this view's `hole` (inf elsewhere): its hole
    pixels lifted by `ref_depth` and splatted onto the 2x2 pixel centres around each (the nearest wins),
    kept within `rel_tol` of this view's own `depth`, then gaps of up to `GAP_PX` between them closed with
    the nearest neighbour's depth (a view that sees the surface larger than the reference does gets more
    pixels than it has points)."""
    rows, cols = np.nonzero(ref_hole & np.isfinite(ref_depth))
    u, v, z = project(camera, backproject(ref, cols + 0.5, rows + 0.5, ref_depth[rows, cols]))
    nearest = np.full(hole.shape, np.inf)
    left, top = np.floor(u - 0.5), np.floor(v - 0.5)
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1)):
        x, y = np.nan_to_num(left + dx, nan=-1).astype(np.int64), np.nan_to_num(top + dy, nan=-1).astype(np.int64)
        ok = (z > 0) & (x >= 0) & (x < camera.width) & (y >= 0) & (y < camera.height)
        x, y, zz = x[ok], y[ok], z[ok]
        ok = hole[y, x] & (np.abs(zz - depth[y, x]) <= rel_tol * depth[y, x])
        np.minimum.at(nearest, (y[ok], x[ok]), zz[ok])
    for _ in range(GAP_PX):
        gaps = hole & ~np.isfinite(nearest)
        grown = cv2.erode(np.where(np.isfinite(nearest), nearest, BIG).astype(np.float32), np.ones((3, 3), np.uint8))
        fill = gaps & (grown < BIG)
        if not fill.any():
            break
        nearest[fill] = grown[fill]
    return nearest


def write_reference_fill(scene_dir: SceneLayout, cameras: list[Camera], train: list[int], holes_of: HolesLayout,
                         inpainted: InpaintedLayout, dilation: int, consensus: bool = True,
                         plane: PlaneFill | None = None) -> dict:
    """Rewrite the training images of `scene_dir` (a completion's training scene) so that every hole
    carries the reference view's fill; returns what was done."""
    fills = {}
    for i in train:
        camera = cameras[i]
        hole = dilate(read_png(holes_of.mask(camera.name), "mask", camera.size) > 0, dilation)
        if hole.any():
            fills[i] = ViewFill(camera, hole, read_png(inpainted.images / camera.name, size=camera.size),
                                read_depth(inpainted.depth / exr_name(camera.name), camera.size))
    if not fills:
        return {"reference": None, "carried_px": 0, "hole_px": 0}
    r = reference_view(fills)
    ref = fills[r]
    if consensus:
        ref = dataclasses.replace(ref, image=consensus_fill(fills, r))
        path = scene_dir.images / ref.camera.name
        image = read_png(path, size=ref.camera.size)
        image[ref.hole] = ref.image[ref.hole]
        write_png(path, image)

    def carry_into(view: ViewFill) -> tuple[int, int]:
        path = scene_dir.images / view.camera.name
        image, landed = carry_fill(view.camera, view.hole, view.depth, read_png(path, size=view.camera.size),
                                   ref.camera, ref.hole, ref.depth, ref.image)
        write_png(path, image)
        return int(landed.sum()), int(view.hole.sum())

    counts = each_view(carry_into, [view for i, view in fills.items() if i != r])
    carried, total = sum(c for c, _ in counts), sum(t for _, t in counts)
    report = {"reference": ref.camera.name, "consensus": consensus, "carried_px": carried, "hole_px": total,
              "carried_share": round(carried / total, 4) if total else None}
    if plane is not None:
        report["plane_texture"] = _plane_texture(scene_dir, fills, plane)
    return report


def _plane_texture(scene_dir: SceneLayout, fills: dict[int, ViewFill], plane: PlaneFill) -> dict:
    """The on-plane part of every view's hole rewritten from the plane's texture (engine.complete.plane_texture),
    over the carried fill."""
    from engine.complete.plane_texture import write_plane_texture

    views = list(fills.values())
    paths = [scene_dir.images / view.camera.name for view in views]
    images, report, texture = write_plane_texture(
        [read_png(path, size=view.camera.size) for path, view in zip(paths, views, strict=True)],
        [view.camera for view in views], [view.hole for view in views], [view.depth for view in views],
        plane.plane, plane.footprint, plane.inpainter)
    for path, image in zip(paths, images, strict=True):
        write_png(path, image)
    write_png(Path(scene_dir.root) / "plane_texture.png", texture)
    return report
