"""engine.io.visibility tests points against views in torch (on the GPU when there is one) with the arithmetic of
engine.formats.cameras' numpy project and sample_nearest, which Blender's Python shares: the two must give the same
answers, edges and non-finite coordinates included."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from engine.formats.cameras import Camera, project, sample_nearest
from engine.io.visibility import inside_visual_hull, project_points, sample_pixels, seen_by_any

pytestmark = pytest.mark.fast


def _cameras(count: int, rng: np.random.Generator) -> list[Camera]:
    cameras = []
    for k in range(count):
        angle = 2 * np.pi * k / count
        centre = np.array([2.0 * np.cos(angle), 2.0 * np.sin(angle), 0.3])
        forward = -centre / np.linalg.norm(centre)
        right = np.cross(forward, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        rotation = np.stack([right, np.cross(forward, right), forward])
        cameras.append(Camera(f"{k}.png", 40, 30, 35.0 + rng.uniform(), 35.0, 20.3, 14.7, rotation,
                              -rotation @ centre))
    return cameras


def _numpy_seen(points, cameras, depths, rel_tol, occluders, near):
    """seen_by_any written out with the numpy camera functions: any view with the point in frame, in front, not
    behind its depth (the tolerance growing past `near`) and not under its occluder."""
    seen = np.zeros(len(points), bool)
    for camera, depth, occluder in zip(cameras, depths, occluders, strict=True):
        u, v, z = project(camera, points)
        surface, inside = sample_nearest(depth, u, v)
        tol = rel_tol * np.maximum(1.0, surface / near)
        seen |= inside & (z > 0) & (z <= surface * (1 + tol)) & ~sample_nearest(occluder, u, v)[0]
    return seen


def test_torch_visibility_answers_as_the_numpy_camera_functions():
    rng = np.random.default_rng(3)
    cameras = _cameras(6, rng)
    depths = [rng.uniform(1.0, 3.0, (30, 40)).astype(np.float32) for _ in cameras]
    for depth in depths:
        depth[rng.random(depth.shape) < 0.1] = np.inf  # sky
    occluders = [rng.random((30, 40)) < 0.2 for _ in cameras]
    points = rng.uniform(-1.5, 1.5, (4000, 3))
    points[:5] = cameras[0].center  # z = 0 in view 0: non-finite pixel coordinates
    seen = seen_by_any(points, cameras, depths, 0.01, occluders, near=1.5, device=torch.device("cpu"))
    expected = _numpy_seen(points, cameras, depths, 0.01, occluders, 1.5)
    assert 0.05 < expected.mean() < 0.95  # both answers occur
    assert np.array_equal(seen, expected)
    hull = inside_visual_hull(points, cameras, occluders, min_views=2, share=0.3, device=torch.device("cpu"))
    framed = sum(sample_nearest(m, *project(c, points)[:2])[1] & (project(c, points)[2] > 0)
                 for c, m in zip(cameras, occluders, strict=True))
    hits = sum(np.logical_and(*sample_nearest(m, *project(c, points)[:2])) & (project(c, points)[2] > 0)
               for c, m in zip(cameras, occluders, strict=True))
    assert np.array_equal(hull, (framed >= 2) & (hits >= 0.3 * framed))


def test_pixel_lookup_floors_and_rejects_what_lies_outside_as_numpy_does():
    camera = _cameras(1, np.random.default_rng(0))[0]
    image = np.arange(30 * 40, dtype=np.float32).reshape(30, 40)
    u = np.array([0.0, 0.999, 39.999, 40.0, -0.001, np.nan, np.inf, -np.inf, 1e12, 12.5])
    v = np.array([0.0, 29.999, 0.5, 3.0, 3.0, 1.0, 1.0, 1.0, 1.0, 29.0])
    value, inside = sample_nearest(image, u, v)
    t_value, t_inside = sample_pixels(torch.as_tensor(image), torch.as_tensor(u), torch.as_tensor(v))
    assert np.array_equal(inside, t_inside.numpy()) and np.array_equal(value, t_value.numpy())
    points = np.random.default_rng(1).uniform(-2, 2, (50, 3))
    for ours, theirs in zip(project_points(camera, torch.as_tensor(points)), project(camera, points), strict=True):
        assert np.allclose(ours.numpy(), theirs, rtol=1e-12, atol=1e-9)
