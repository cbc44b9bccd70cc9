"""benchmarks/grow_sweep.py's split of a hole into what the removed scene renders on the support plane and the rest
(its colour keep is engine.inpaint.keep's, tested in tests/inpaint/test_keep.py)."""

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

