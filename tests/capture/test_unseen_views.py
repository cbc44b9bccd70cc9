"""A test view's pixels that no training view saw (a generated scene's unseen/): surfaces out of every training
view's frame, and sky in directions no training view had in frame or saw as sky. The seen-only PSNR leaves them
out, so sky past the training views' edges does not count as a training's failure."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from engine.formats.cameras import Camera, pixel_grid, project
from engine.io.visibility import exact_tolerance, unseen_view_pixels


def yawed(degrees: float, name: str = "v.png") -> Camera:
    """A 64x48 camera at the origin, turned `degrees` about the vertical axis (OpenCV axes: y down)."""
    a = np.radians(degrees)
    rotation = np.array([[np.cos(a), 0.0, -np.sin(a)], [0.0, 1.0, 0.0], [np.sin(a), 0.0, np.cos(a)]])
    return Camera(name=name, width=64, height=48, fx=62.0, fy=62.0, cx=32.0, cy=24.0, R=rotation, t=np.zeros(3))


def directions(camera: Camera) -> np.ndarray:
    """(H, W, 3) each pixel's ray in world axes, with camera z = 1."""
    u, v = pixel_grid(camera)
    rays = np.stack([(u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, np.ones_like(u)], axis=-1)
    return rays @ camera.R  # R^T r, row-vector form


def floor_depth(camera: Camera) -> np.ndarray:
    """z-depth of a floor 1 m below the camera; the sky (infinite) above the horizon."""
    down = directions(camera)[..., 1]
    with np.errstate(divide="ignore"):
        return np.where(down > 1e-6, 1.0 / down, np.inf)


def test_what_lies_past_the_training_views_frame_is_unseen_floor_and_sky_alike():
    train, test = yawed(0.0, "a.png"), yawed(40.0)
    unseen = unseen_view_pixels(test, floor_depth(test), [train], [floor_depth(train)], exact_tolerance([test]))
    u, v, z = project(train, directions(test))
    outside = ~((z > 0) & (u >= 0) & (u < train.width) & (v >= 0) & (v < train.height))
    assert 0.2 < outside.mean() < 0.8  # the turn puts part of the test view out of the training view's frame
    sky = ~np.isfinite(floor_depth(test))
    # the floor within 2 m, met at 30 degrees or more (farther, its depth changes by more than the exact tolerance
    # from one pixel to the next, and a nearest-pixel depth test misses some of it, as any does), and the sky
    clear = sky | (floor_depth(test) < 2.0)
    assert (unseen != outside)[clear].mean() < 0.01  # both the floor's and the sky's part, to a pixel's rounding
    assert (unseen & sky).any() and (unseen & ~sky).any()
    same = unseen_view_pixels(train, floor_depth(train), [train], [floor_depth(train)], exact_tolerance([train]))
    assert not same.any()


def test_sky_that_a_training_view_saw_as_a_wall_is_unseen():
    """The training view had those directions in frame but showed something there, so it never saw that sky."""
    camera = yawed(0.0)
    wall = np.full((48, 64), 5.0)
    unseen = unseen_view_pixels(camera, floor_depth(camera), [camera], [wall], exact_tolerance([camera]))
    sky = ~np.isfinite(floor_depth(camera))
    assert unseen[sky].all()


def test_the_seen_only_gap_leaves_out_what_no_training_view_saw(tmp_path):
    """Three views of one splat: the third's truth differs in a corner its unseen mask covers. Over all pixels
    it lies far below the others; over the seen ones it is the first view again."""
    from engine.capture.scene import Scene
    from engine.io.gaussians import init_from_points, new_classifier
    from engine.metrics.evaluate import evaluate_views
    from engine.render.rasterize import CameraTensors, render

    cameras = [Camera(f"000{i}.png", 16, 12, 20.0, 20.0, 8.0, 6.0, np.eye(3), np.array([0.0, 0.0, 4.0]))
               for i in range(3)]
    points = np.random.default_rng(0).normal(size=(50, 3)) * 0.3
    splat = init_from_points(points, np.full((50, 3), 128, np.uint8), sh_degree=0)
    shown = render(splat, CameraTensors.from_camera(cameras[0], torch.device("cpu")), 0, depth=False).rgb
    rendered = (shown.clamp(0, 1) * 255).round().numpy().astype(np.uint8)
    images = [rendered.copy() for _ in range(3)]
    images[1] = np.clip(rendered.astype(int) + 6, 0, 255).astype(np.uint8)
    images[2][:4, :4] = 255 - images[2][:4, :4]  # a cloud no training view saw
    corner = np.zeros((12, 16), bool)
    corner[:4, :4] = True
    scene = Scene(root=tmp_path, cameras=cameras, images=images, points=points,
                  colors=np.full((50, 3), 128, np.uint8), train=[], test=[0, 1, 2],
                  unseen={0: np.zeros((12, 16), bool), 1: np.zeros((12, 16), bool), 2: corner})
    metrics = evaluate_views(scene, [0, 1, 2], splat, new_classifier(1), 0, torch.device("cpu"))
    seen = metrics["psnr_seen_per_view"]
    assert metrics["psnr_per_view"]["0002.png"] < metrics["psnr_per_view"]["0000.png"] - 3
    assert seen["0002.png"] == pytest.approx(seen["0000.png"], abs=1.0)  # ~60 dB: the truth's rounding
    assert metrics["worst_view_gap_seen"] < metrics["worst_view_gap"] - 1
