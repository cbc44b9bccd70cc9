"""The engine's turntable (engine/pictures/turntable.py) where it decides things itself: which Gaussians were the
object, and what it refuses. The whole command, MP4 included, runs in the Blender tests (script and operator)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from engine.base.errors import InputError
from engine.formats.layout import RemovedLayout, RunLayout
from engine.io.gaussians import init_from_points
from engine.io.ply_io import save_ply
from engine.pictures.turntable import TurntableConfig, make_turntable, object_centre


def _run(tmp_path: Path) -> tuple[RunLayout, RemovedLayout, np.ndarray]:
    points = np.random.default_rng(0).normal(size=(40, 3))
    points[:6] += 10.0  # the object: six Gaussians far from the rest
    splat = init_from_points(points, np.full((40, 3), 128, np.uint8), sh_degree=1)
    run, removed = RunLayout(tmp_path / "run"), RemovedLayout(tmp_path / "run" / "removed")
    removed.root.mkdir(parents=True)
    save_ply(run.point_cloud, splat)
    save_ply(removed.point_cloud, {k: v[6:] for k, v in splat.items()})
    return run, removed, points


def test_the_orbit_centres_on_the_gaussians_the_removal_took_away(tmp_path: Path):
    run, removed, points = _run(tmp_path)
    assert np.allclose(object_centre(run, removed), points[:6].mean(0), atol=1e-5)
    save_ply(removed.point_cloud, init_from_points(points, np.full((40, 3), 128, np.uint8), sh_degree=1))
    with pytest.raises(InputError, match="removed nothing"):
        object_centre(run, removed)


def test_a_turntable_refuses_cameras_that_are_no_list_and_writes_nothing(tmp_path: Path):
    run, removed, _ = _run(tmp_path)
    run.config_json.write_text(json.dumps({"scene": str(tmp_path / "scene")}))
    cameras = tmp_path / "cameras.json"
    cameras.write_text(json.dumps({"name": "0000.png"}))
    out = tmp_path / "tt"
    with pytest.raises(InputError, match="no list of cameras"):
        make_turntable(TurntableConfig(run=str(run.root), out=str(out), cameras=str(cameras), device="cpu"))
    assert not out.exists() and not any(p.name.startswith(".tt") for p in tmp_path.iterdir())
