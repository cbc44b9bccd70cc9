"""`clean`: stray Gaussians deleted at once into a new run, by opacity, size, distance from the subject and a
crop box, the run's objects cut to match (no scene is trained: a run folder is written by hand)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from engine.base.errors import InputError
from engine.cli import main
from engine.edit.clean import CleanConfig, run_clean
from engine.formats.layout import RunLayout
from engine.formats.splat_files import read_splat_file
from engine.formats.splat_ply import property_names, write_vertices

pytestmark = pytest.mark.fast


def hand_made_run(root: Path) -> RunLayout:
    """Ten Gaussians: 0-3 the subject (object_1) at the origin, 4 faint, 5 huge, 6 far, 7-9 background near."""
    run = RunLayout(root)
    root.mkdir()
    n = 10
    columns = {name: np.zeros(n, np.float32) for name in property_names(0, with_identity=False)}
    columns["x"][6] = 50.0
    columns["x"][7:] = [1.0, 2.0, -1.0]
    columns["opacity"][:] = 3.0
    columns["opacity"][4] = -5.0
    columns["scale_0"][:], columns["scale_1"][:], columns["scale_2"][:] = -4.0, -4.0, -4.0
    columns["scale_0"][5] = 2.0
    columns["rot_0"][:] = 1.0
    write_vertices(run.point_cloud, columns)
    run.config_json.write_text(json.dumps({"scene": ""}))
    run.segments.root.mkdir()
    np.save(run.segments.ids, np.array([1, 1, 1, 1, 0, 0, 0, 2, 2, 0], np.uint8))
    run.segments.objects_json.write_text(json.dumps([{"id": 1, "name": "object_1"}, {"id": 2, "name": "object_2"}]))
    return run


def test_each_rule_deletes_its_strays_and_the_objects_follow(tmp_path: Path):
    run = hand_made_run(tmp_path / "run")
    report = run_clean(CleanConfig(run=str(run.root), min_opacity=0.1, max_size=1.0, max_distance=10.0,
                                   crop=[-0.5, -1, -1, 2.5, 1, 1]))
    assert report["by_rule"] == {"opacity": 1, "size": 1, "distance": 1, "crop": 2} and report["deleted"] == 4
    out = RunLayout(str(run.root) + "-clean")
    kept = read_splat_file(out.point_cloud)
    assert kept["x"].tolist() == [0, 0, 0, 0, 1, 2]  # the subject, then the background the box holds
    assert np.load(out.segments.ids).tolist() == [1, 1, 1, 1, 2, 2] and out.config_json.is_file()
    assert len(read_splat_file(run.point_cloud)) == 10  # the input run is untouched


def test_clean_from_the_command_line_and_its_one_line_errors(tmp_path: Path):
    run = hand_made_run(tmp_path / "run")
    assert main(["clean", "--run", str(run.root), "--max-size", "1", "--out", str(tmp_path / "small")]) == 0
    assert len(read_splat_file(tmp_path / "small" / "point_cloud.ply")) == 9
    assert main(["clean", "--run", str(run.root)]) == 2  # no rule given
    with pytest.raises(InputError, match="delete all 10"):
        run_clean(CleanConfig(run=str(run.root), crop=[100, 100, 100, 101, 101, 101], out=str(tmp_path / "none")))


def test_around_cameras_deletes_the_gaussians_that_hold_a_camera_of_the_scene(tmp_path: Path):
    """Gaussian 5 (std e^2 = 7.4 along x, centred at the origin) holds a camera 3 from the origin; none of the
    small ones does. With the rule turned off the same run keeps all ten."""
    from engine.formats.cameras import Camera
    from engine.io.colmap_model import ColmapModel, write_model

    run = hand_made_run(tmp_path / "run")
    camera = Camera(name="a.png", width=64, height=48, fx=50.0, fy=50.0, cx=32.0, cy=24.0, R=np.eye(3),
                    t=np.array([0.0, 0.0, 3.0]))  # centre (0, 0, -3), looking along +z at the origin
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    write_model(tmp_path / "scene" / "sparse" / "0", ColmapModel([camera], points, np.full((3, 3), 128, np.uint8)))
    run.config_json.write_text(json.dumps({"scene": str(tmp_path / "scene")}))
    with pytest.raises(InputError, match="nothing to clean"):
        run_clean(CleanConfig(run=str(run.root), out=str(tmp_path / "none")))
    report = run_clean(CleanConfig(run=str(run.root), around_cameras=True))
    assert report["by_rule"] == {"around_cameras": 0}  # the huge one is 7.4 long along x, thin along z
    vertices = read_splat_file(run.point_cloud)
    columns = {name: np.array(vertices[name]) for name in vertices.dtype.names}
    columns["scale_2"][5] = 2.0  # now as long along z: the camera lies at 0.4 sigma
    write_vertices(run.point_cloud, columns)
    report = run_clean(CleanConfig(run=str(run.root), out=str(tmp_path / "cleaned"), around_cameras=True))
    assert report["by_rule"] == {"around_cameras": 1}
    kept = read_splat_file(tmp_path / "cleaned" / "point_cloud.ply")
    assert len(kept) == 9 and 2.0 not in kept["scale_2"]
