"""One fill for every view: the hole inpainted once, in a reference view, and carried to the others by depth.

Inpainting each view on its own gives neighbouring views different fills, and a scene trained on them
averages those into blur (AuraFusion360 and 3DTexMOR fill once and reproject; the benchmark paper's
Init inpaints per view). Here the reference is the training view whose hole is largest (it sees most of
what is missing); every other training view's hole pixel is lifted with that view's own inpainted depth,
projected into the reference and given the reference's inpainted colour there, when the reference's
inpainted depth agrees (within `rel_tol`: the point is the surface the reference filled, not something
in front of it). Pixels the reference cannot vouch for keep their own view's fill. Colours outside the
holes are untouched.
"""

from __future__ import annotations

import numpy as np

from engine.formats.cameras import Camera, backproject, pixel_grid, project, sample_nearest
from engine.formats.layout import HolesLayout, InpaintedLayout, SceneLayout
from engine.io.image_io import exr_name, read_depth, read_png, write_png
from engine.io.masks import dilate

REL_TOL = 0.03  # two independently inpainted depths of one surface agree to a few per cent


def reference_view(holes: dict[int, np.ndarray]) -> int:
    """The view with the most hole pixels."""
    return max(holes, key=lambda i: int(holes[i].sum()))


def carry_fill(camera: Camera, hole: np.ndarray, depth: np.ndarray, image: np.ndarray, ref: Camera,
               ref_depth: np.ndarray, ref_image: np.ndarray, rel_tol: float = REL_TOL) -> tuple[np.ndarray, int]:
    """`image` with its `hole` pixels replaced by the reference's fill where the depths agree, and how
    many were."""
    u, v = pixel_grid(camera)
    ys, xs = np.nonzero(hole & np.isfinite(depth))
    points = backproject(camera, u[ys, xs], v[ys, xs], depth[ys, xs])
    ru, rv, rz = project(ref, points)
    surface, inside = sample_nearest(ref_depth, ru, rv)
    agree = inside & (rz > 0) & np.isfinite(surface) & (np.abs(rz - surface) <= rel_tol * surface)
    out = image.copy()
    cols = np.clip(np.floor(ru[agree]).astype(int), 0, ref.width - 1)
    rows = np.clip(np.floor(rv[agree]).astype(int), 0, ref.height - 1)
    out[ys[agree], xs[agree]] = ref_image[rows, cols]
    return out, int(agree.sum())


def write_reference_fill(scene_dir: SceneLayout, cameras: list[Camera], train: list[int], holes_of: HolesLayout,
                         inpainted: InpaintedLayout, dilation: int) -> dict:
    """Rewrite the training images of `scene_dir` (a completion's training scene) so that every hole
    carries the reference view's fill; returns what was done."""
    holes = {i: dilate(read_png(holes_of.mask(cameras[i].name), "mask", cameras[i].size) > 0, dilation)
             for i in train}
    holes = {i: h for i, h in holes.items() if h.any()}
    if not holes:
        return {"reference": None, "carried_px": 0, "hole_px": 0}
    r = reference_view(holes)
    ref, ref_image = cameras[r], read_png(inpainted.images / cameras[r].name, size=cameras[r].size)
    ref_depth = read_depth(inpainted.depth / exr_name(ref.name), ref.size)
    carried = total = 0
    for i, hole in holes.items():
        if i == r:
            continue
        camera = cameras[i]
        path = scene_dir.images / camera.name
        depth = read_depth(inpainted.depth / exr_name(camera.name), camera.size)
        image, count = carry_fill(camera, hole, depth, read_png(path, size=camera.size), ref, ref_depth, ref_image)
        write_png(path, image)
        carried, total = carried + count, total + int(hole.sum())
    return {"reference": ref.name, "carried_px": carried, "hole_px": total,
            "carried_share": round(carried / total, 4) if total else None}
