"""Keeping what the removed render already shows like the hole's surroundings instead of filling it."""

from __future__ import annotations

import numpy as np

from engine.inpaint.keep import like_ring, ring_px


def _slab_with_remnant(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A grey slab with noise (std 8 levels), a square hole whose left half renders the slab carried on and
    whose right half a dark remnant of the object."""
    rng = np.random.default_rng(seed)
    image = np.clip(rng.normal(128, 8, (120, 160, 3)), 0, 255).astype(np.uint8)
    hole = np.zeros((120, 160), bool)
    hole[40:80, 60:100] = True
    image[40:80, 80:100] = 30
    return image, hole


def test_the_render_is_kept_where_it_looks_like_the_ring_and_a_remnant_is_not():
    image, hole = _slab_with_remnant()
    kept = like_ring(image, hole, 1.5)
    assert not kept[~hole].any()
    assert kept[40:80, 60:80].mean() > 0.8  # the slab carried on under the object
    assert not kept[40:80, 80:100].any()  # the dark remnant is filled
    assert not like_ring(image, hole, 0.0).any()  # 0: fill all


def test_the_ring_scales_with_the_image():
    assert ring_px(320) == 6 and ring_px(640) == 13 and ring_px(64) == 3
