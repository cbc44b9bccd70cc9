"""The surface depth the hole masks use, the generator's exact effect regions, and the one-fill-for-every-view
reprojection (engine.complete.reference_fill): hand-built views with a worked-out answer."""

from __future__ import annotations

import math

import numpy as np

from engine.formats.cameras import Camera, backproject, pixel_grid
from tests.gaussian_grids import gaussians


def front_camera() -> Camera:
    return Camera(name="c.png", width=40, height=30, fx=40.0, fy=40.0, cx=20.0, cy=15.0, R=np.eye(3),
                  t=np.zeros(3))


def wall_seen_by(camera: Camera, depth: np.ndarray) -> np.ndarray:
    """What `camera` sees of a wall textured by position (red = x, green = y) at `depth`: one 3D point, one
    colour in every view, so a carried fill can be checked pixel by pixel."""
    u, v = pixel_grid(camera)
    points = backproject(camera, u, v, depth)
    return (np.stack([points[..., 0], points[..., 1], np.zeros_like(u)], -1) * 40 + 128).astype(np.uint8)


def test_surface_depth_is_where_opacity_passes_a_half_not_the_blend_of_everything_behind():
    from engine.render.rasterize import CameraTensors
    from engine.render.surface_depth import surface_depth

    xs = np.arange(-3.0, 3.0, 0.1)
    sheet = np.stack(np.meshgrid(xs, xs, indexing="ij"), -1).reshape(-1, 2)
    front = np.concatenate([sheet, np.full((len(sheet), 1), 2.0)], 1)  # a see-through sheet at z = 2
    back = np.concatenate([sheet, np.full((len(sheet), 1), 5.0)], 1)  # an opaque wall at z = 5
    both = gaussians(np.concatenate([front, back]), np.full((2 * len(sheet), 3), 0.5), scale=0.08)
    both["opacities"][: len(sheet)] = math.log(0.3 / 0.7)  # the sheet alone passes a little over half
    camera = CameraTensors.from_camera(front_camera(), "cpu")
    from engine.render.rasterize import render

    expected = render(both, camera, 0, backend="reference").depth
    depth, alpha = surface_depth(both, camera, "reference")
    centre = (slice(10, 20), slice(15, 25))
    assert float(expected[centre].mean()) > 2.6  # the blend lies well behind the sheet
    np.testing.assert_allclose(depth[centre].numpy(), 2.0, atol=0.05)
    both["opacities"][: len(sheet)] = math.log(0.1 / 0.9)  # too thin to count: the wall is the surface
    np.testing.assert_allclose(surface_depth(both, camera, "reference")[0][centre].numpy(), 5.0, atol=0.1)


def test_the_effect_region_is_what_changed_outside_the_object_noise_and_the_object_left_out():
    from engine.capture.scene_build import effect_region

    rng = np.random.default_rng(0)
    gt = rng.integers(60, 200, (40, 50, 3)).astype(np.uint8)
    image = np.clip(gt.astype(int) + rng.integers(-4, 5, gt.shape), 0, 255).astype(np.uint8)  # render noise
    target = np.zeros((40, 50), bool)
    target[5:15, 5:15] = True
    image[target] = 255  # the object itself
    image[15:25, 10:30] = gt[15:25, 10:30] // 2  # its shadow
    image[33, 40] = 0  # one hot pixel
    region = effect_region(image, gt, target)
    expected = np.zeros_like(target)
    expected[15:25, 10:30] = True
    expected[15, 10:16] = False  # the object's antialiased edge (grown by one pixel) is not its effect
    assert (region ^ expected).sum() <= 12 and not region[target].any() and not region[33, 40]


def test_one_fill_is_carried_to_another_view_of_the_same_surface():
    from engine.complete.reference_fill import carry_fill
    from engine.io.masks import dilate

    ref = front_camera()
    other = Camera(name="o.png", width=40, height=30, fx=40.0, fy=40.0, cx=20.0, cy=15.0, R=np.eye(3),
                   t=np.array([-0.3, 0.0, 0.0]))  # 0.3 to the right
    wall = 4.0
    ref_depth, depth = np.full((30, 40), wall), np.full((30, 40), wall)
    ref_image = wall_seen_by(ref, ref_depth)
    hole = np.zeros((30, 40), bool)
    hole[10:20, 12:28] = True
    image = np.zeros((30, 40, 3), np.uint8)
    ref_hole = dilate(hole, 4)  # the reference sees the same patch of wall 3 px further left
    filled, carried = carry_fill(other, hole, depth, image, ref, ref_hole, ref_depth, ref_image)
    assert np.array_equal(carried, hole)
    truth = wall_seen_by(other, depth)
    assert np.abs(filled[hole].astype(int) - truth[hole]).max() <= 6  # nearest pixel of the reference
    assert not filled[~hole].any()
    # the reference's depth places the fill: this view's own depth fill 5% off changes nothing
    assert np.array_equal(carry_fill(other, hole, depth * 1.05, image, ref, ref_hole, ref_depth, ref_image)[0], filled)
    # where the reference filled something else (an occluder in front of the wall), nothing is carried
    ref_depth[:, :] = 1.0
    assert not carry_fill(other, hole, depth, image, ref, ref_hole, ref_depth, ref_image)[1].any()


def test_a_view_that_sees_the_fill_larger_than_the_reference_gets_all_of_it_and_no_speckle():
    """The reference's pixels land 2.5 px apart in a view 2.5x closer to the wall: splatted colours leave
    every other column and row of the hole with the view's own fill; the fill read back covers it all."""
    from engine.complete.reference_fill import carry_fill

    ref = front_camera()
    near = Camera(name="n.png", width=40, height=30, fx=40.0, fy=40.0, cx=20.0, cy=15.0, R=np.eye(3),
                  t=np.array([0.0, 0.0, -2.4]))  # 2.4 closer: the wall at 1.6 instead of 4
    ref_depth, depth = np.full((30, 40), 4.0), np.full((30, 40), 1.6)
    ref_image = wall_seen_by(ref, ref_depth)
    ref_hole = np.zeros((30, 40), bool)
    ref_hole[5:25, 8:32] = True
    hole = np.zeros((30, 40), bool)
    hole[10:20, 12:28] = True
    filled, carried = carry_fill(near, hole, depth, np.zeros((30, 40, 3), np.uint8), ref, ref_hole, ref_depth,
                                 ref_image)
    assert np.array_equal(carried, hole)
    assert np.abs(filled[hole].astype(int) - wall_seen_by(near, depth)[hole]).max() <= 2


def test_a_hole_of_more_than_32767_pixels_is_carried_as_a_small_one():
    """A real capture's hole is the object's whole footprint: 50,000 pixels crashed cv2.remap (its maps are
    images under 32767 px a side). The same wall as above at 8x the size: every hole pixel carried, right."""
    from engine.complete.reference_fill import carry_fill, sample_bilinear
    from engine.io.masks import dilate

    k = 8
    ref = Camera(name="c.png", width=40 * k, height=30 * k, fx=40.0 * k, fy=40.0 * k, cx=20.0 * k, cy=15.0 * k,
                 R=np.eye(3), t=np.zeros(3))
    other = Camera(name="o.png", width=40 * k, height=30 * k, fx=40.0 * k, fy=40.0 * k, cx=20.0 * k, cy=15.0 * k,
                   R=np.eye(3), t=np.array([-0.3, 0.0, 0.0]))
    depth = np.full((30 * k, 40 * k), 4.0)
    hole = np.zeros(depth.shape, bool)
    hole[5 * k:25 * k, 6 * k:34 * k] = True
    assert hole.sum() > 32767
    ref_image = wall_seen_by(ref, depth)
    filled, carried = carry_fill(other, hole, depth, np.zeros_like(ref_image), ref, dilate(hole, 4 * k), depth,
                                 ref_image)
    assert np.array_equal(carried, hole)
    assert np.abs(filled[hole].astype(int) - wall_seen_by(other, depth)[hole]).max() <= 2
    # the sampler itself, against a bilinear read by hand, at 40,000 points
    rng = np.random.default_rng(0)
    image = rng.random((50, 60)).astype(np.float32)
    x, y = rng.uniform(0, 58, 40_000), rng.uniform(0, 48, 40_000)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0
    by_hand = (image[y0, x0] * (1 - fx) * (1 - fy) + image[y0, x0 + 1] * fx * (1 - fy)
               + image[y0 + 1, x0] * (1 - fx) * fy + image[y0 + 1, x0 + 1] * fx * fy)
    assert np.abs(sample_bilinear(image, x, y) - by_hand).max() < 0.01


def test_the_reference_is_the_fill_the_other_views_agree_with_not_the_largest_hole():
    from engine.complete.reference_fill import ViewFill, reference_view
    from engine.io.masks import dilate

    wall = 4.0
    fills = {}
    for i, shift in enumerate((0.0, 0.3, -0.3)):
        camera = Camera(name=f"{i}.png", width=40, height=30, fx=40.0, fy=40.0, cx=20.0, cy=15.0, R=np.eye(3),
                        t=np.array([-shift, 0.0, 0.0]))
        image = wall_seen_by(camera, np.full((30, 40), wall))
        hole = np.zeros((30, 40), bool)
        hole[10:20, 12:28] = True
        fills[i] = ViewFill(camera, hole, image, np.full((30, 40), wall))
    outlier = fills[2]
    outlier.image[:] = 0  # one view filled its hole with something else entirely (a dark border, say)
    outlier.hole = dilate(outlier.hole, 3)  # and its hole is the largest: the first rule's choice
    assert reference_view(fills) in (0, 1)


def test_the_consensus_fill_is_nearer_the_truth_than_any_one_views_fill():
    """Five views of a wall each fill the hole with the truth plus their own noise (independent draws of
    an inpainter) and a sixth pasted black there: the median carried into the reference is closer to the
    truth than any view's own fill, the black one left out."""
    from engine.complete.reference_fill import ViewFill, consensus_fill

    wall, rng, fills = 4.0, np.random.default_rng(0), {}
    hole = np.zeros((30, 40), bool)
    hole[10:20, 12:28] = True
    for i, shift in enumerate((0.0, 0.1, -0.1, 0.2, -0.2, 0.15)):
        camera = Camera(name=f"{i}.png", width=40, height=30, fx=40.0, fy=40.0, cx=20.0, cy=15.0, R=np.eye(3),
                        t=np.array([-shift, 0.0, 0.0]))
        image = wall_seen_by(camera, np.full((30, 40), wall)).astype(int)
        image[hole] = 0 if i == 5 else image[hole] + rng.integers(-40, 41, (int(hole.sum()), 3))
        fills[i] = ViewFill(camera, hole, np.clip(image, 0, 255).astype(np.uint8), np.full((30, 40), wall))
    truth = wall_seen_by(fills[0].camera, np.full((30, 40), wall)).astype(float)

    def error(image: np.ndarray) -> float:
        return float(np.abs(image[hole] - truth[hole]).mean())

    median = consensus_fill(fills, 0)
    assert error(median) < 0.75 * min(error(f.image) for f in fills.values())
    assert np.array_equal(median[~hole], fills[0].image[~hole])
