"""Gaussians no training view tells from the black background are found, and nothing the views need
(engine.train.background_floaters): on the skull capture black, opaque Gaussians drawn over the photos' black
background in every training view covered four test views of nine."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import torch

from engine.formats.cameras import Camera
from engine.io.gaussians import concat
from engine.render.rasterize import CameraTensors, render
from engine.train.background_floaters import background_floaters
from tests.gaussian_grids import gaussians

CPU = torch.device("cpu")


def looking_at(name: str, centre: np.ndarray) -> Camera:
    """A 64x64 camera at `centre` facing the origin, y down."""
    forward = -centre / np.linalg.norm(centre)
    right = np.cross(forward, [0.0, -1.0, 0.0]) if abs(forward[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    rotation = np.stack([right, down, forward])
    return Camera(name, 64, 64, 40.0, 40.0, 32.0, 32.0, rotation, -rotation @ centre)


def ball(radius: float = 0.3, step: float = 0.06) -> np.ndarray:
    axis = np.arange(-radius, radius + 1e-9, step)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    return grid[np.linalg.norm(grid, axis=1) <= radius]


def scene() -> tuple[dict, dict[str, slice], list[Camera], Camera]:
    """A white ball at the origin with a black spot on its front, three training cameras in front, and a black,
    opaque floater off to the side where the training views see it only over the black background; a test camera
    on the side sees it in front of the ball."""
    white = ball()
    parts = {"ball": gaussians(white, np.ones_like(white), scale=0.04),
             "spot": gaussians(np.array([[0.0, 0.0, 0.34]]), np.zeros((1, 3)), scale=0.05),
             "floater": gaussians(np.array([[1.5, 0.0, 0.0]]), np.zeros((1, 3)), opacity=0.99, scale=0.3)}
    slices, start = {}, 0
    for name, part in parts.items():
        slices[name], start = slice(start, start + len(part["means"])), start + len(part["means"])
    train = [looking_at(f"t{k}", np.array([x, 0.0, 3.0])) for k, x in enumerate((-1.0, 0.0, 1.0))]
    return concat(*parts.values()), slices, train, looking_at("side", np.array([3.0, 0.0, 0.0]))


def pictures(splats: dict, cameras: list[Camera]) -> list[torch.Tensor]:
    return [render(splats, CameraTensors.from_camera(c, CPU), 0, depth=False, identity=False).rgb for c in cameras]


def largest_change(splats: dict, floaters: np.ndarray, cameras: list[Camera]) -> float:
    kept = {k: v[torch.as_tensor(~floaters)] for k, v in splats.items()}
    return max(float((a - b).abs().max()) for a, b in zip(pictures(splats, cameras), pictures(kept, cameras),
                                                            strict=True))


def test_the_black_floater_goes_the_spot_stays_and_no_training_view_changes():
    splats, parts, train, side = scene()
    floaters = background_floaters(splats, train, 0, CPU)
    assert floaters[parts["floater"]].all() and not floaters[parts["spot"]].any()
    assert largest_change(splats, floaters, train) < 0.02
    kept = {k: v[torch.as_tensor(~floaters)] for k, v in splats.items()}
    side_before, side_after = pictures(splats, [side])[0], pictures(kept, [side])[0]
    centre = (slice(30, 34), slice(30, 34))  # where the side camera sees the ball
    assert float(side_before[centre].mean()) < 0.1 < 0.5 < float(side_after[centre].mean())  # it shows again


def test_two_sides_of_a_wall_that_each_hide_the_other_come_back_where_removing_both_opens_a_hole():
    """A white wall of two opaque sheets seen from both sides: from each side the near sheet hides the far one,
    so one at a time the Gaussians inside both are candidates; removed together they open a hole in the wall,
    and the joint check returns what the views need."""
    axis = np.arange(-0.5, 0.5001, 0.1)
    sheet = np.stack(np.meshgrid(axis, axis, indexing="ij"), -1).reshape(-1, 2)
    sides = np.concatenate([np.c_[sheet, np.full(len(sheet), z)] for z in (0.02, -0.02)])
    wall = gaussians(sides, np.ones_like(sides), opacity=0.99, scale=0.1)
    cameras = [looking_at("front", np.array([0.0, 0.0, 3.0])), looking_at("back", np.array([0.0, 0.0, -3.0]))]
    alone = background_floaters(wall, cameras, 0, CPU, rounds=0)
    assert largest_change(wall, alone, cameras) > 0.5  # a hole
    joint = background_floaters(wall, cameras, 0, CPU)
    assert largest_change(wall, joint, cameras) < 0.02


def test_a_run_with_the_option_reports_the_floaters_it_emptied(living_scene: Path, tmp_path: Path):
    from engine.train.config import TrainConfig
    from engine.train.run import train

    config = TrainConfig(scene=str(living_scene), out=str(tmp_path / "run"), preset="tiny", device="cpu",
                         background_floaters=0.01).resolved()
    metrics = train(dataclasses.replace(config, steps=2))
    assert isinstance(metrics["background_floaters"], int)
