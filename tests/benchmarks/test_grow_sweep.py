"""benchmarks/grow_sweep.py's split of a hole into what the removed scene renders on the support plane and the rest."""

from __future__ import annotations

import numpy as np

from benchmarks.grow_sweep import on_plane
from engine.formats.cameras import Camera


def test_on_plane_takes_the_rendered_surface_on_the_plane_not_in_front_of_it_nor_none():
    """A camera facing a plane 5 units away (n.x + d = 0 with n = z, d = -5): depth 5 lies on it, 4.5 (an object's
    remnant in front, 10% nearer) does not, nor does a pixel with no surface (inf)."""
    camera = Camera("0000.png", 8, 6, 10.0, 10.0, 4.0, 3.0, np.eye(3), np.zeros(3))
    depth = np.full((6, 8), 5.0, np.float32)
    depth[:, 6:] = 4.5
    depth[0, 0] = np.inf
    kept = on_plane(camera, depth, (np.array([0.0, 0.0, 1.0]), -5.0), tol=0.02)
    assert kept[1:, :6].all() and not kept[:, 6:].any() and not kept[0, 0]
    assert not on_plane(camera, depth, None, tol=0.02).any()


def test_like_ring_keeps_what_looks_like_the_surface_around_the_hole_not_a_dark_remnant():
    """A grey surface (noise of 5 levels) with a hole whose left half renders the same grey and right half a dark
    remnant: the grey half is kept, the remnant is not, nor anything outside the hole."""
    from benchmarks.grow_sweep import like_ring

    rng = np.random.default_rng(0)
    image = np.clip(rng.normal(120, 5, (40, 40, 3)), 0, 255).astype(np.uint8)
    hole = np.zeros((40, 40), bool)
    hole[10:30, 10:30] = True
    image[10:30, 20:30] = 20
    alike = like_ring(image, hole, z=1.0)
    assert alike[10:30, 10:20].mean() > 0.5 and not alike[10:30, 20:30].any() and not alike[~hole].any()
