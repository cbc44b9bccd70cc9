"""What of the removed render to keep in a hole instead of filling it: the pixels that already look like the
surface around the hole.

3DGS often carries a support on under an object that stood on it (the slab under a statue, a floor under a
chair) and renders it there in about the right colour; a 2D fill, which reads only the hole's border, replaces
that with whatever the border holds (a shadow band's lit edge, the next tile). A pixel is kept where its colour
lies within Z standard deviations of the colours in the ring just outside the hole, per channel; a remnant of the
object (a dark contact blob, a translucent shell) stands out from the ring and is filled. The views' kept pixels
are renders of one 3D scene, so they agree across views as the carried fill does.
"""

from __future__ import annotations

import numpy as np

from engine.io.masks import dilate

RING_SHARE = 0.02  # the ring's width as a share of the image width (6 px at 320, 13 at 640)
LEVEL_FLOOR = 4.0  # 8-bit levels added to each channel's spread: a flat ring does not make every pixel "unlike"


def ring_px(width: int) -> int:
    """The ring's width in px for an image `width` wide (3 at least)."""
    return max(3, round(RING_SHARE * width))


def like_ring(image: np.ndarray, hole: np.ndarray, z: float, ring: int | None = None) -> np.ndarray:
    """(H, W) bool: pixels of `hole` whose colour lies within `z` standard deviations (per channel, plus
    LEVEL_FLOOR) of the colours in the ring `ring` px wide around it (default ring_px). None of them where z <= 0
    or the ring has fewer than 20 pixels (a hole that fills the view)."""
    if z <= 0:
        return np.zeros(hole.shape, bool)
    around = dilate(hole, ring_px(image.shape[1]) if ring is None else ring) & ~hole
    if around.sum() < 20:
        return np.zeros(hole.shape, bool)
    colours = image[around].astype(np.float64)
    score = np.abs((image.astype(np.float64) - colours.mean(0)) / (colours.std(0) + LEVEL_FLOOR)).max(-1)
    return hole & (score < z)
