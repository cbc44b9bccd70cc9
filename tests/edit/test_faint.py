"""Faint Gaussians that render only inside the removed object's region go with it (engine.edit.faint): a
hand-built floor round a box, seen from a ring of cameras, with a translucent shell on the box."""

from __future__ import annotations

import numpy as np
import torch

from engine.edit.faint import faint_inside, rendered_weights
from engine.io.gaussians import concat
from tests.edit.test_diffuse import floor_and_box, region_of, ring_of_cameras
from tests.gaussian_grids import gaussians

DEVICE = torch.device("cpu")


def scene_with_shell():
    """The floor (opaque, kept), the box (removed), a faint shell over the box's top, a faint blob floating beside
    the box and an opaque one inside the shell; (gaussians, removed, kinds, the box's points) with kinds 0 floor,
    1 box, 2 shell, 3 faint blob beside, 4 opaque inside."""
    floor, box, _ = floor_and_box()
    xs = np.arange(-0.1, 0.11, 0.05)
    shell = np.stack(np.meshgrid(xs, xs, indexing="ij"), -1).reshape(-1, 2)
    shell = np.concatenate([shell, np.full((len(shell), 1), 0.55)], 1)
    beside = np.array([[0.6, 0.0, 0.3]])
    inside = np.array([[0.0, 0.0, 0.45]])
    parts = [gaussians(floor, np.full((len(floor), 3), 0.6)), gaussians(box, np.full((len(box), 3), 0.3)),
             gaussians(shell, np.full((len(shell), 3), 0.7), opacity=0.1, scale=0.015),
             gaussians(beside, np.full((1, 3), 0.7), opacity=0.1, scale=0.015),
             gaussians(inside, np.full((1, 3), 0.7), opacity=0.9, scale=0.015)]
    kinds = np.concatenate([np.full(len(p["means"]), k) for k, p in enumerate(parts)])
    everything = parts[0]
    for part in parts[1:]:
        everything = concat(everything, part)
    return everything, kinds == 1, kinds, box


def test_the_faint_shell_that_renders_only_where_the_box_stood_goes_and_the_rest_stays():
    everything, removed, kinds, box = scene_with_shell()
    cameras = ring_of_cameras()
    regions = [region_of(c, box) for c in cameras]
    candidates = kinds != 0  # the floor is the support
    faint = faint_inside(everything, removed, candidates, cameras, regions, DEVICE)
    assert faint[kinds == 2].all()
    assert not faint[(kinds == 0) | (kinds == 1) | (kinds == 3) | (kinds == 4)].any()
    spared = faint_inside(everything, removed, kinds == 3, cameras, regions, DEVICE)  # not a candidate: stays
    assert not spared[kinds == 2].any()


def test_a_gaussians_weight_is_what_it_adds_to_the_pixels_inside_and_in_all():
    """One Gaussian alone, its region the whole frame in one view and nothing in the other: its weight inside is
    the first view's alone, and in all twice that (the two views of the ring see it alike)."""
    one = gaussians(np.array([[0.0, 0.0, 0.3]]), np.full((1, 3), 0.5), opacity=0.5, scale=0.03)
    cameras = ring_of_cameras(2)
    full = np.ones((cameras[0].height, cameras[0].width), bool)
    empty = ~full
    inside, total = rendered_weights(one, cameras, [full, empty], DEVICE)
    _, alone = rendered_weights(one, cameras[:1], [full], DEVICE)
    assert total[0] > 0 and np.isclose(inside[0], alone[0], rtol=1e-5)
    assert np.isclose(total[0], 2 * alone[0], rtol=0.05)
