"""The photos' colour for hole pixels some photo saw: the hand-built wall of test_border, a red square in front of
it, seen by three cameras side by side. Behind the square's edges the side views see the wall; its middle nobody
saw."""

from __future__ import annotations

import numpy as np

from engine.edit.border import photo_ranges
from engine.edit.photo_fill import invented, photo_view
from engine.formats.cameras import backproject, pixel_grid
from engine.io.masks import dilate
from engine.io.visibility import seen_by_any
from tests.edit.test_border import RED, photo
from tests.edit.test_holes import camera_at, depth_seen_from


def _setup():
    a, b, c = camera_at(0.0), camera_at(0.5), camera_at(-0.5)
    cameras = [a, b, c]
    photos = [photo(cam, with_object=True) for cam in cameras]
    depths = [depth_seen_from(cam, with_object=False)[0] for cam in cameras]  # the removed scene: the wall
    occluders = [dilate(depth_seen_from(cam, with_object=True)[1], 1) for cam in cameras]
    return cameras, photos, depths, occluders


def test_the_pixels_a_photo_saw_take_the_walls_colour_and_the_rest_are_invented():
    cameras, photos, depths, occluders = _setup()
    a = cameras[0]
    _, region = depth_seen_from(a, with_object=True)
    image, seen = photo_view(a, region, depths[0], cameras, photos, depths, occluders, 0.01, None)
    u, v = pixel_grid(a)
    points = backproject(a, u, v, depths[0])
    truth = seen_by_any(points.reshape(-1, 3), cameras, depths, 0.01, occluders).reshape(region.shape) & region
    assert (seen == truth).all()
    assert 0.2 * region.sum() < seen.sum() < region.sum()  # the sides behind the square, not its middle
    (low, high), = photo_ranges([photo(a, with_object=False)])  # the wall as `a` would see it, within a pixel
    assert not (image[seen] == RED).all(axis=-1).any()  # no photo's object is pasted
    assert ((image[seen] >= low[seen]) & (image[seen] <= high[seen])).all()
    assert (invented(region, seen) == region & ~seen).all()
    assert (invented(region, None) == region).all()  # a holes folder without photos: all invented


def test_a_photo_whose_shadow_or_object_covers_a_point_gives_it_no_colour():
    """Occluders decide: with the right-hand view's whole frame hidden (its shadow, say), only the left-hand view's
    side of the square gets a colour; with every view hidden, none."""
    cameras, photos, depths, occluders = _setup()
    a = cameras[0]
    _, region = depth_seen_from(a, with_object=True)
    _, both = photo_view(a, region, depths[0], cameras, photos, depths, occluders, 0.01, None)
    shadowed = [occluders[0], np.ones_like(occluders[1]), occluders[2]]
    _, one = photo_view(a, region, depths[0], cameras, photos, depths, shadowed, 0.01, None)
    assert one.any() and one.sum() < both.sum() and not (one & ~both).any()
    hidden = [np.ones_like(o) for o in occluders]
    _, none = photo_view(a, region, depths[0], cameras, photos, depths, hidden, 0.01, None)
    assert not none.any()
