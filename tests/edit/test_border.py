"""The hole's border that the render gets wrong: a hand-built wall seen by three cameras, a red square in front of
it, and a removed render right everywhere but a red remnant stuck to the hole's edge and a speck apart from it."""

from __future__ import annotations

import numpy as np

from engine.edit.border import photo_ranges, wrong_border
from engine.formats.cameras import backproject, pixel_grid
from engine.io.masks import dilate
from engine.io.visibility import seen_by_any
from tests.edit.test_holes import SQUARE, WALL, F, camera_at, depth_seen_from

RED = np.array([220, 30, 30], np.uint8)


def wall_colour(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """A checker of 0.2 m cells in two greys, and a gentle ramp: every pixel tells where on the wall it is."""
    cell = (np.floor(x / 0.2) + np.floor(y / 0.2)).astype(int) % 2
    grey = np.where(cell == 1, 170, 80) + np.clip(x * 10, -20, 20)
    return np.repeat(grey[..., None], 3, axis=-1).astype(np.uint8)


def photo(camera, with_object: bool) -> np.ndarray:
    u, v = pixel_grid(camera)
    image = wall_colour(-camera.t[0] + (u - camera.cx) / F * WALL, (v - camera.cy) / F * WALL)
    if with_object:
        _, hits = depth_seen_from(camera, with_object=True)
        image[hits] = RED
    return image


def test_a_remnant_stuck_to_the_hole_is_border_and_the_right_band_and_a_stray_speck_are_not():
    a, b, c = camera_at(0.0), camera_at(0.5), camera_at(-0.5)
    cameras = [a, b, c]
    photos = [photo(cam, with_object=True) for cam in cameras]
    depths = [depth_seen_from(cam, with_object=False)[0] for cam in cameras]  # the removed scene: the wall
    occluders = [dilate(depth_seen_from(cam, with_object=True)[1], 1) for cam in cameras]  # as `holes` grows them
    _, region = depth_seen_from(a, with_object=True)
    hole = region.copy()
    rendered = photo(a, with_object=False)
    ys, xs = np.nonzero(region)
    remnant = np.zeros_like(hole)
    remnant[ys.min() + 3:ys.min() + 9, xs.max() + 1:xs.max() + 5] = True  # a remnant on the hole's right edge
    speck = np.zeros_like(hole)
    speck[ys.max() - 3:ys.max() - 1, xs.min() - 10:xs.min() - 8] = True  # red too, but 8 px from the hole
    rendered[remnant | speck] = RED
    wrong = wrong_border(a, hole, rendered, depths[0], cameras, photo_ranges(photos), depths, occluders, 0.01, SQUARE,
                         width_px=12)
    assert wrong[remnant].all()
    assert not wrong[speck].any()
    # the rest of the band stays, rendered as the photos show it, but where every photo's object hid it (at the
    # square's top and bottom edge, level in all three views): nothing says it is right there
    u, v = pixel_grid(a)
    points = backproject(a, u, v, depths[0])
    hidden = ~seen_by_any(points.reshape(-1, 3), cameras, depths, 0.01, occluders).reshape(hole.shape)
    assert not (wrong & ~dilate(remnant, 2) & ~dilate(hidden, 1)).any()
    assert (wrong & ~dilate(remnant, 2)).sum() < 0.01 * (dilate(hole, 12) & ~hole).sum()


def test_a_band_no_photo_saw_is_wrong_and_one_the_object_hid_in_every_photo_too():
    """A band pixel that no training photo shows (each hid it behind its object) has nothing to say it is right."""
    a = camera_at(0.0)
    _, region = depth_seen_from(a, with_object=True)
    hole = np.zeros_like(region)
    ys, xs = np.nonzero(region)
    hole[ys.min() + 5:ys.max() - 5, xs.min() + 5:xs.max() - 5] = True  # a hole inside the object's region
    depth = depth_seen_from(a, with_object=False)[0]
    rendered = photo(a, with_object=False)
    wrong = wrong_border(a, hole, rendered, depth, [a], photo_ranges([photo(a, True)]), [depth], [region], 0.01, SQUARE,
                         width_px=3)
    ring = dilate(hole, 3) & ~hole
    assert wrong[ring].all()  # the whole band lies in the object's region, which its only photo hid


def test_without_border_relit_the_band_takes_none_of_the_pixels_remove_relit(tiny_stages):
    """The photos show the plush's shadow where `remove` relit the table, so by their colour the relit band is
    wrong, and with `--border-relit` the band fills it; without (the default) those pixels stay as the fill's
    context. The masks differ by relit pixels only, and by some (the flag does something here)."""
    from engine.edit.holes import HoleConfig, run_holes
    from engine.formats.layout import RemovedLayout
    from engine.io.image_io import read_png

    masks = {}
    for relit in (True, False):
        masks[relit] = tiny_stages["work"] / f"holes_border_relit_{relit}"
        run_holes(HoleConfig(run=str(tiny_stages["run"]), removed=str(tiny_stages["removed"]), out=str(masks[relit]),
                             border_relit=relit))
    assert not HoleConfig().border_relit
    effects, dropped = RemovedLayout(tiny_stages["removed"]).effects, 0
    for name in sorted(p.name for p in masks[False].glob("*.png")):
        taken = read_png(masks[True] / name, "mask") > 0
        kept = read_png(masks[False] / name, "mask") > 0
        relit = read_png(effects.mask(name), "mask", taken.shape[::-1]) > 0
        assert not (kept & ~taken).any(), name
        assert not (taken & ~kept & ~relit).any(), name
        dropped += int((taken & ~kept).sum())
    assert dropped > 0
