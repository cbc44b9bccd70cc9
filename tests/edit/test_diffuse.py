"""The support the object hid from many views loses its view-dependent colour on removal (engine.edit.diffuse): a
hand-built floor round a box, seen from a ring of cameras."""

from __future__ import annotations

import numpy as np
import torch

from engine.edit.diffuse import diffuse_support, hidden_share
from engine.edit.effects import EffectsConfig
from engine.edit.support_plane import object_core, object_support
from engine.formats.cameras import Camera, project
from engine.io.masks import dilate
from tests.gaussian_grids import SPACING, gaussians

W, H, F = 96, 72, 80.0


def looking_at(eye: np.ndarray, target: np.ndarray, k: int) -> Camera:
    """A pinhole camera at `eye` looking at `target`, +z up in the world (the camera's y points down)."""
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    rotation = np.stack([right, down, forward])
    return Camera(name=f"{k:02d}.png", width=W, height=H, fx=F, fy=F, cx=W / 2, cy=H / 2, R=rotation,
                  t=-rotation @ eye)


def ring_of_cameras(count: int = 16) -> list[Camera]:
    angles = np.linspace(0, 2 * np.pi, count, endpoint=False)
    return [looking_at(np.array([2.0 * np.cos(a), 2.0 * np.sin(a), 1.6]), np.array([0.0, 0.0, 0.2]), k)
            for k, a in enumerate(angles)]


def region_of(camera: Camera, box: np.ndarray) -> np.ndarray:
    """(H, W) bool: the pixels the box's points fall on, closed by one pixel."""
    u, v, z = project(camera, box)
    mask = np.zeros((H, W), bool)
    ok = (z > 0) & (u >= 0) & (u < W) & (v >= 0) & (v < H)
    mask[v[ok].astype(int), u[ok].astype(int)] = True
    return dilate(mask, 1)


def floor_and_box():
    xs = np.arange(-1.2, 1.2, SPACING)
    floor = np.stack(np.meshgrid(xs, xs, indexing="ij"), -1).reshape(-1, 2)
    floor = np.concatenate([floor, np.zeros((len(floor), 1))], 1)
    floor = floor[~((np.abs(floor[:, 0]) < 0.15) & (np.abs(floor[:, 1]) < 0.15))]
    bx = np.arange(-0.14, 0.15, SPACING)
    box = np.stack(np.meshgrid(bx, bx, np.arange(0.02, 0.6, SPACING), indexing="ij"), -1).reshape(-1, 3)
    remaining = gaussians(floor, np.full((len(floor), 3), 0.6))
    remaining["shN"] = torch.as_tensor(np.random.default_rng(0).normal(0, 0.1, (len(floor), 15, 3)),
                                       dtype=torch.float32)
    return floor, box, remaining


def test_the_floor_the_box_hid_from_many_views_is_made_diffuse_and_the_rest_keeps_its_view_dependence():
    floor, box, remaining = floor_and_box()
    removed = gaussians(box, np.full((len(box), 3), 0.3))
    up = np.array([0.0, 0.0, 1.0])
    core = object_core(removed, up)
    plane = object_support(floor, core, up)
    cameras = ring_of_cameras()
    regions = [region_of(c, box) for c in cameras]
    others = np.zeros(len(floor), bool)
    others[(np.abs(floor[:, 0] - 0.2) < 0.03) & (np.abs(floor[:, 1]) < 0.1)] = True  # another object's foot
    out, count = diffuse_support(remaining, core, plane, cameras, regions, list(range(len(cameras))), others,
                                 EffectsConfig())
    zeroed = (out["shN"].abs().sum((1, 2)) == 0).numpy()
    distance = np.abs(floor[:, :2]).max(1)
    assert count == zeroed.sum() > 0
    assert zeroed[(distance < 0.3) & ~others].mean() > 0.9  # beside the box: hidden from many of the ring's views
    assert not zeroed[distance > 0.9].any()  # far out the box hid it from few views: its view-dependence stays
    assert not zeroed[others].any()
    assert torch.equal(out["sh0"], remaining["sh0"])  # the DC term, the colour's mean over directions, stays
    kept = torch.from_numpy(~zeroed)
    assert torch.equal(out["shN"][kept], remaining["shN"][kept])


def test_a_point_behind_the_box_in_some_views_is_hidden_in_that_share_of_them():
    _, box, _ = floor_and_box()
    cameras = ring_of_cameras()
    regions = [region_of(c, box) for c in cameras]
    points = np.array([[0.2, 0.0, 0.0], [1.1, 1.1, 0.0], [0.0, 0.0, 2.0]])  # beside it, far off, above it
    share = hidden_share(points, cameras, regions, box, list(range(len(cameras))))
    assert 0.1 < share[0] < 0.7
    assert share[1] <= 1 / 16
    assert share[2] == 0.0  # in front of the box wherever it falls in its region
