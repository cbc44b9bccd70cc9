"""The hole on the support plane filled once in the plane's texture (engine.complete.plane_texture): a floor with a
known texture seen by cameras around a removed object's footprint, whose middle no view saw."""

from __future__ import annotations

import numpy as np
import pytest

from engine.edit.support_plane import Footprint
from engine.formats.cameras import Camera, backproject, pixel_grid, project

UP = np.array([0.0, 0.0, 1.0])
FLOOR = (UP, 0.0)  # z = 0
UNSEEN = 0.1  # the floor within this radius of the origin is what no view saw


def looking_at_origin(name: str, azimuth: float, elevation: float = 50.0, distance: float = 1.5) -> Camera:
    az, el = np.radians(azimuth), np.radians(elevation)
    centre = distance * np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    forward = -centre / np.linalg.norm(centre)
    right = np.cross(forward, UP)
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    R = np.stack([right, down, forward])
    return Camera(name=name, width=80, height=60, fx=70.0, fy=70.0, cx=40.0, cy=30.0, R=R, t=-R @ centre)


def floor_colour(points: np.ndarray) -> np.ndarray:
    """A smooth texture by position: what a fill from the border can get nearly right."""
    return np.clip(np.stack([128 + 300 * points[..., 0], 128 + 300 * points[..., 1],
                             np.full(points.shape[:-1], 90.0)], -1), 0, 255).astype(np.uint8)


def view(camera: Camera) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(image, z-depth, hole) of the floor: the hole is the unseen disc, painted black as a removal leaves it."""
    u, v = pixel_grid(camera)
    ray = backproject(camera, u, v, np.ones_like(u)) - camera.center
    depth = -camera.center[2] / ray[..., 2]
    points = camera.center + ray * depth[..., None]
    hole = np.hypot(points[..., 0], points[..., 1]) < UNSEEN
    image = floor_colour(points)
    image[hole] = 0
    return image, depth, hole


@pytest.fixture(scope="module")
def floor():
    from engine.inpaint.registry import create

    cameras = [looking_at_origin(f"{k}.png", azimuth) for k, azimuth in enumerate(range(0, 360, 45))]
    images, depths, holes = zip(*(view(c) for c in cameras), strict=True)
    footprint = Footprint(np.zeros(3), 0.15, UP)
    return cameras, list(images), list(depths), list(holes), footprint, create("telea")


def test_the_texture_is_the_floor_seen_straight_on_and_its_unseen_middle_is_what_needs_filling(floor):
    from engine.complete.plane_texture import gather, texture_grid

    cameras, images, depths, holes, footprint, _ = floor
    grid = texture_grid(FLOOR, footprint, cameras)
    texture, seen, needed = gather(grid, cameras, images, holes, depths)
    centres = grid.centres().reshape(grid.size, grid.size, 3)
    radius = np.hypot(centres[..., 0], centres[..., 1])
    error = np.abs(texture.astype(int) - floor_colour(centres).astype(int))[seen & (radius > UNSEEN + 0.02)]
    assert error.mean() < 2.0 and seen[radius > UNSEEN + 0.02].mean() > 0.95, error.mean()
    assert needed[radius < UNSEEN - 0.02].all() and not needed[radius > UNSEEN + 0.02].any()


def test_every_view_gets_one_fill_at_each_floor_point_close_to_the_truth(floor):
    from engine.complete.plane_texture import write_plane_texture

    cameras, images, depths, holes, footprint, telea = floor
    filled, report, _ = write_plane_texture(images, cameras, holes, depths, FLOOR, footprint, telea)
    assert report["placed_share"] > 0.95, report
    truth = [floor_colour(backproject(c, *pixel_grid(c), d)) for c, d in zip(cameras, depths, strict=True)]
    error = np.mean([np.abs(f.astype(int) - t.astype(int))[h].mean() for f, t, h in zip(filled, truth, holes,
                                                                                      strict=True)])
    assert error < 12, error  # black as the removal left it: ~100
    # the same floor point in two views: view 0's hole pixels looked up in view 4, across the object
    u, v = pixel_grid(cameras[0])
    points = backproject(cameras[0], u[holes[0]], v[holes[0]], depths[0][holes[0]])
    u4, v4, _ = project(cameras[4], points)
    other = filled[4][np.floor(v4).astype(int), np.floor(u4).astype(int)]
    assert np.abs(other.astype(int) - filled[0][holes[0]].astype(int)).mean() < 4


def test_hole_pixels_whose_depth_is_off_the_plane_keep_their_fill(floor):
    from engine.complete.plane_texture import apply_texture, texture_grid

    cameras, images, depths, holes, footprint, _ = floor
    grid = texture_grid(FLOOR, footprint, cameras)
    texture = np.full((grid.size, grid.size, 3), 200, np.uint8)
    raised = depths[0] * 0.8  # something in front of the floor there, as the inpainted depth says
    out, placed = apply_texture(grid, texture, np.ones((grid.size, grid.size), bool), cameras[0], holes[0], raised,
                                images[0])
    assert not placed.any() and (out == images[0]).all()
