"""Large holes filled at a coarse scale: what keeps the slow inpainters at real image sizes within a second.

A real capture's hole is the whole footprint of the object a photo is centred on: 100k pixels of a 1 MP view.
Frequency-selective reconstruction (FSR) took 30 s for such a view, the exemplar inpainter minutes: their cost
grows with the hole's area times the area they search. Both fill a hole that large with content from its
surroundings that varies slowly at the hole's own scale (a smooth continuation; a texture copied patch by
patch), so they run on the hole's neighbourhood downscaled by an integer factor `scale` until the hole has at
most `max_hole_px` pixels, and the result is brought back: FSR's fill upsampled (`Coarse.up`), the exemplar's
patches copied again at full resolution from where they came from (engine.inpaint.inpainters.exemplar), so its
texture keeps its sharpness. A hole within the limit is filled as before, at full resolution.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numpy as np


@dataclass(frozen=True)
class Coarse:
    """The hole's neighbourhood (`rows`, `cols` of the image, padded to a multiple of `scale` by repeating its
    edge) and the integer factor it is downscaled by."""

    rows: slice
    cols: slice
    scale: int
    pad: tuple[int, int]  # rows and columns added below and right to make the crop a multiple of scale

    def down(self, image: np.ndarray) -> np.ndarray:
        """The crop, each scale x scale block averaged."""
        crop = np.pad(image[self.rows, self.cols], ((0, self.pad[0]), (0, self.pad[1])) + ((0, 0),) * (image.ndim - 2),
                      mode="edge")
        h, w = crop.shape[:2]
        small = cv2.resize(crop, (w // self.scale, h // self.scale), interpolation=cv2.INTER_AREA)
        return small.reshape(small.shape[:2] + image.shape[2:])

    def down_mask(self, mask: np.ndarray) -> np.ndarray:
        """A coarse pixel is in the hole when any of its fine pixels is."""
        return self.down(mask.astype(np.float32)) > 0

    def up(self, small: np.ndarray, image: np.ndarray) -> np.ndarray:
        """`image` with its crop replaced by `small` upsampled (bilinear), cut back to the crop's size."""
        h = (self.rows.stop - self.rows.start) + self.pad[0]
        w = (self.cols.stop - self.cols.start) + self.pad[1]
        big = cv2.resize(small, (w, h), interpolation=cv2.INTER_LINEAR).reshape((h, w) + image.shape[2:])
        out = image.copy()
        out[self.rows, self.cols] = big[:h - self.pad[0], :w - self.pad[1]].astype(image.dtype)
        return out


def grown_box(mask: np.ndarray, grow: Callable[[int], int]) -> tuple[slice, slice]:
    """The rows and columns of `mask`'s bounding box, grown on each side by `grow(extent)` px (extent: the box's
    height for the rows, its width for the columns), within the image: the neighbourhood an inpainter reads."""
    box = []
    for index, size in zip(np.nonzero(mask), mask.shape, strict=True):
        step = grow(int(index.max() - index.min() + 1))
        box.append(slice(max(index.min() - step, 0), min(index.max() + step + 1, size)))
    return box[0], box[1]


def coarse_view(mask: np.ndarray, max_hole_px: int) -> Coarse | None:
    """Where and how much to downscale for a hole of more than `max_hole_px` pixels (None: fill as it is). The
    crop is the hole's bounding box grown by its own size on each side (what the exemplar searches), within
    the image."""
    area = int(mask.sum())
    if max_hole_px <= 0 or area <= max_hole_px:
        return None
    scale = math.ceil(math.sqrt(area / max_hole_px))
    rows, cols = grown_box(mask, lambda extent: extent)
    pad = (-(rows.stop - rows.start) % scale, -(cols.stop - cols.start) % scale)
    return Coarse(rows, cols, scale, pad)


def fill_coarse(fill, image: np.ndarray, mask: np.ndarray, max_hole_px: int) -> np.ndarray:
    """`fill(image, mask)` itself for a small hole; for a large one, `fill` on the downscaled neighbourhood and
    its result upsampled into the hole (the caller keeps pixels outside the mask)."""
    coarse = coarse_view(mask, max_hole_px)
    if coarse is None:
        return fill(image, mask)
    small = fill(np.ascontiguousarray(coarse.down(image)), coarse.down_mask(mask))
    return coarse.up(small, image)
