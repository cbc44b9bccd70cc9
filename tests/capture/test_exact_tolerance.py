"""The exact holes' depth tolerance follows the pixel: wide enough for Cycles' one-sample depth jitter on a
grazing surface, narrow enough that a point a few millimetres behind an occluder is not 'seen'."""

from __future__ import annotations

import numpy as np

from engine.formats.cameras import Camera, backproject, pixel_grid
from engine.io.visibility import DEFAULT_REL_TOL, exact_tolerance, seen_by_any

SLOPE, NEAR = 2.75, 0.8  # a plane z = NEAR + SLOPE * y in camera coordinates: rays graze it at about 20 degrees


def camera(width: int) -> Camera:
    focal = width * 35.0 / 36.0  # the generator's 35 mm lens on a 36 mm sensor
    return Camera(name="a.png", width=width, height=width * 3 // 4, fx=focal, fy=focal, cx=width / 2,
                  cy=width * 3 / 8, R=np.eye(3), t=np.zeros(3))


def plane_depth(cam: Camera, v: np.ndarray) -> np.ndarray:
    return NEAR / (1.0 - SLOPE * (v - cam.cy) / cam.fy)


def grazing_degrees(cam: Camera, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The angle between each pixel's ray and the plane."""
    rays = np.stack([(u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, np.ones_like(u)], axis=-1)
    normal = np.array([0.0, -SLOPE, 1.0]) / np.hypot(SLOPE, 1.0)
    return np.degrees(np.arcsin(np.abs(rays @ normal) / np.linalg.norm(rays, axis=-1)))


def test_tolerance_is_two_pixels_of_focal_and_never_above_one_percent():
    assert abs(exact_tolerance([camera(640)]) - 2.0 / 622.22) < 1e-5
    assert exact_tolerance([camera(96)]) == DEFAULT_REL_TOL


def test_a_grazing_plane_with_one_sample_depth_jitter_is_seen_everywhere():
    """Each pixel's depth taken at a random point of the pixel, as Cycles' depth pass does; the plane's points
    at pixel centres, where rays meet it at 15 degrees or more, must all be seen by that depth map (at shallower
    angles other views see them). A tolerance of a tenth of it misses many."""
    cam, rng = camera(640), np.random.default_rng(0)
    u, v = pixel_grid(cam)
    exact = plane_depth(cam, v)
    rows = (exact > 0) & (grazing_degrees(cam, u, v) >= 15.0)
    jittered = plane_depth(cam, v + rng.uniform(-0.5, 0.5, v.shape))
    points = backproject(cam, u[rows], v[rows], exact[rows])
    tolerance = exact_tolerance([cam])
    assert seen_by_any(points, [cam], [jittered], tolerance).all()
    assert (~seen_by_any(points, [cam], [jittered], tolerance / 10)).mean() > 0.2


def test_a_point_millimetres_behind_an_occluder_is_not_seen():
    """A card at 0.8 m in front of every pixel and points 4 mm behind it: 1% of depth (8 mm) called them seen,
    which made the tabletop's exact holes too small; the pixel's tolerance at 640 px does not."""
    cam = camera(640)
    u, v = pixel_grid(cam)
    card = np.full(u.shape, NEAR)
    points = backproject(cam, u.ravel(), v.ravel(), np.full(u.size, NEAR + 0.004))
    assert seen_by_any(points, [cam], [card], DEFAULT_REL_TOL).all()
    assert not seen_by_any(points, [cam], [card], exact_tolerance([cam])).any()
