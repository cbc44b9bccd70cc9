"""What a completion may change (engine.complete.hole_region): the Gaussians that render into the hole and nowhere
else, on two cameras looking at a wall, without a trained run."""

from __future__ import annotations

import numpy as np

from engine.capture.scene import Scene
from engine.complete.hole_region import hole_bound
from engine.formats.cameras import Camera

W, H = 40, 30


def camera(name: str, x: float) -> Camera:
    """A camera at (x, 0, -4) looking down +z at the wall z = 0 (OpenCV axes, world = camera rotation)."""
    return Camera(name, W, H, 30.0, 30.0, W / 2, H / 2, np.eye(3), np.array([-x, 0.0, 4.0]))


def scene_of(cameras: list[Camera]) -> Scene:
    images = [np.zeros((H, W, 3), np.uint8) for _ in cameras]
    return Scene(root=".", cameras=cameras, images=images, points=np.zeros((1, 3)), colors=np.zeros((1, 3), np.uint8),
                 train=list(range(len(cameras))), test=[])


def test_only_what_every_view_shows_inside_its_hole_may_change():
    """Left and right cameras, each with a hole around the image centre. A point on the wall straight ahead of
    both holes' overlap is movable; a point the left camera sees outside its hole is fixed; the same point
    hidden from the left camera behind a nearer surface there is movable again; a point no hole contains is
    fixed."""
    cams = [camera("left.png", -0.2), camera("right.png", 0.2)]
    hole = np.zeros((H, W), bool)
    hole[10:20, 14:26] = True  # 12 px wide: +-6 px around the centre, 0.8 world units at the wall
    holes = {0: hole, 1: hole}
    far = {0: np.full((H, W), 4.0), 1: np.full((H, W), 4.0)}  # the wall's depth, seen everywhere
    points = np.array([[0.0, 0.0, 0.0],  # inside both holes
                       [0.65, 0.0, 0.0],  # in the right camera's hole, outside the left one's
                       [2.0, 0.0, 0.0]])  # in no hole
    assert hole_bound(points, scene_of(cams), holes, far).tolist() == [True, False, False]
    hidden = {0: np.full((H, W), 2.0), 1: far[1]}  # the left camera sees a surface at depth 2 in front of the wall
    assert hole_bound(points, scene_of(cams), holes, hidden).tolist() == [True, True, False]
