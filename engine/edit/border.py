"""The band around a hole that the removed render gets wrong, judged by the photos that saw it.

Why: the removed render's pixels next to a hole are its worst (a remnant's edge left by the removal, the contact
shade relit in part, a support's edge seen through, blur), and a 2D fill reads its colours from there. Growing
every hole by 4% of the image's width before inpainting replaced them (docs/BENCHMARKS.md, "Hole masks": Ref-telea
+4.5 dB on tiny CPU runs) but replaced the right border with them, and that border is the fill's context: on exact
data the growth alone costs the fill 4 dB (`benchmarks/fill_2d.py`: telea 29.62 in the hole alone, 25.48 grown by
13 px). So a pixel of the band joins the hole only where the render shows something other than what was there:

- its rendered surface point (the removed depth) is looked up in every training photo that saw it: in frame, in
  front, not behind that view's removed render's surface (the holes' own visibility test,
  engine.io.visibility.seen_by_any's) and not inside that view's object region (grown by OCCLUDER_SHARE of the
  width: the photo shows the object there, its edge blended into the pixels beside it);
- it is wrong where most of those photos contradict its colour: it lies more than `levels` (8-bit) outside the
  range of the photo's 3x3 neighbourhood there in some channel (render and photo disagree by up to half a pixel,
  so at a sharp edge either side is right); and where no photo saw it (nothing says it is right);
- the wrong pixels, each grown by a pixel (the render blurs an error into its neighbours, and the photos' range
  beside the object's edge takes in its colour), count where they join the hole: a stray speck in the band is the
  model's noise, not a remnant.

The photos show the object's shadow where `remove` relit it, so a relit band disagrees and is filled, as the
uniform growth filled it; the rest of the band, rendered as the photos show it, stays as context.
"""

from __future__ import annotations

import cv2
import numpy as np
import torch

from engine.base.device import pick_device
from engine.formats.cameras import Camera, backproject, pixel_grid
from engine.io.masks import dilate
from engine.io.visibility import Array, as_tensor, sample_pixels, visible_from

BORDER_SHARE = 0.04  # the band's width as a share of the image width (the old uniform growth's: 13 px at 320)
BORDER_LEVELS = 24.0  # 8-bit levels a band pixel's colour may differ from the photos' before it is wrong
OCCLUDER_SHARE = 0.005  # the object's region in a photo, grown by this share of its width (2 px at 320)


def band_px(width: int, share: float = BORDER_SHARE) -> int:
    """The band's width in px for an image `width` wide (0 where `share` is 0)."""
    return max(1, round(share * width)) if share > 0 else 0


def photo_ranges(photos: list[np.ndarray]) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each photo's per-channel (min, max) over every pixel's 3x3 neighbourhood: a render and a photo of one
    surface disagree by up to half a pixel, so at a sharp edge a pixel's colour lies anywhere between the two
    sides (a checker at 5 px a cell: a third of a band's pixels called wrong by the photos' single pixels)."""
    kernel = np.ones((3, 3), np.uint8)
    return [(cv2.erode(photo, kernel), cv2.dilate(photo, kernel)) for photo in photos]


def contradicted(points: np.ndarray, colours: np.ndarray, cameras: list[Camera],
                 ranges: list[tuple[Array, Array]], depths: list[Array], occluders: list[Array],
                 rel_tol: float, near: float | None, levels: float, device: torch.device | None = None) -> np.ndarray:
    """(N,) bool: whether most of the photos that see each of `points` (N, 3) contradict its rendered colour
    (`colours`, N x 3): it lies more than `levels` outside the photo's range there in some channel. True where no
    photo sees it. Seeing is seen_by_any's test (depths: the views' removed surfaces; occluders: their object
    regions), on `device` as it (engine.io.visibility)."""
    device = device or pick_device("auto")
    points = as_tensor(points, device, torch.float64)
    colours = as_tensor(colours, device, torch.float32)
    seen = torch.zeros(len(points), dtype=torch.int32, device=device)
    against = torch.zeros(len(points), dtype=torch.int32, device=device)
    for camera, (low, high), depth, occluder in zip(cameras, ranges, depths, occluders, strict=True):
        visible, u, v = visible_from(camera, as_tensor(depth, device), points, rel_tol,
                                     as_tensor(occluder, device), near)
        below = sample_pixels(as_tensor(low, device), u, v)[0].float() - levels
        above = sample_pixels(as_tensor(high, device), u, v)[0].float() + levels
        outside = ((colours < below) | (colours > above)).any(dim=1)
        seen += visible
        against += visible & outside
    return ((seen == 0) | (2 * against > seen)).cpu().numpy()


def wrong_border(camera: Camera, hole: np.ndarray, rgb: np.ndarray, depth: np.ndarray, cameras: list[Camera],
                 ranges: list[tuple[Array, Array]], depths: list[Array], occluders: list[Array],
                 rel_tol: float, near: float | None, width_px: int, levels: float = BORDER_LEVELS,
                 device: torch.device | None = None) -> np.ndarray:
    """(H, W) bool: the pixels within `width_px` of `hole` whose render (`rgb`, `depth`: the removed scene's in
    this view) the training photos contradict (`ranges`: photo_ranges of them; the module's docstring), joined to
    the hole."""
    band = dilate(hole, width_px) & ~hole
    if not band.any():
        return band
    ys, xs = np.nonzero(band & np.isfinite(depth) & (depth > 0))
    u, v = pixel_grid(camera)
    points = backproject(camera, u[ys, xs], v[ys, xs], depth[ys, xs])
    wrong = band & ~np.isfinite(depth)  # no surface rendered: nothing there to keep
    wrong[ys, xs] = contradicted(points, rgb[ys, xs], cameras, ranges, depths, occluders, rel_tol, near, levels,
                                 device)
    return _joined(dilate(wrong, 1), hole) & band


def _joined(wrong: np.ndarray, hole: np.ndarray) -> np.ndarray:
    """The `wrong` pixels in a connected piece (8-neighbours) with some pixel of `hole`."""
    count, labels = cv2.connectedComponents((wrong | hole).astype(np.uint8), connectivity=8)
    if count <= 1:
        return np.zeros_like(wrong)
    touching = np.zeros(count, bool)
    touching[np.unique(labels[hole])] = True
    touching[0] = False
    return wrong & touching[labels]
