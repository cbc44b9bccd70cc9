"""The benchmark matrix on the tiny scene: cells run (as Ray tasks, then resumed one after the other), a failing cell
is recorded, a resumed run repeats nothing."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from engine.io.image_io import read_png

REPO = Path(__file__).resolve().parents[2]


def benchmark(scene: Path, out: Path, *extra: str, seeds: tuple[str, ...] = ("0",)) -> subprocess.CompletedProcess:
    args = [sys.executable, str(REPO / "scripts" / "benchmark.py"), "--scenes", str(scene), "--methods", "init",
            "ft3", "--inpainters", "fsr", "lama", "--seeds", *seeds, *extra, "--out", str(out), "--preset", "tiny",
            "--steps", "200", "--complete-steps", "100", "--short-steps", "120", "--max-gaussians", "0",
            "--dilate", "1", "--perceptual", "l1", "--device", "cpu"]
    env = {"PATH": "/usr/bin:/bin", "SPLATFILL_ENGINE_PYTHON": sys.executable, "HOME": str(out)}
    return subprocess.run(args, capture_output=True, text=True, env=env, cwd=REPO, timeout=900)


def test_matrix_runs_records_failures_and_resumes_without_repeating_work(living_scene: Path, tmp_path: Path):
    first = benchmark(living_scene, tmp_path)
    assert first.returncode == 0, first.stderr[-2000:]
    cells = json.loads((tmp_path / "results.json").read_text())
    assert [(c["method"], c["status"]) for c in cells] == [
        ("Init-fsr[warm]", "done"), ("FT-fsr(3)[l1]", "done"), ("Init-lama[warm]", "failed"),
        ("FT-lama(3)[l1]", "failed")]
    assert "LAMA_MODEL" in cells[2]["reason"]  # no weights: recorded, and the matrix went on
    settings = cells[0]["settings"]  # what the cell ran with, in its record
    assert settings["base"]["steps"] == 200 and settings["base"]["max_gaussians"] == 0
    assert settings["scene"] == {"views": 8, "train": 7, "test": 1, "size": [96, 72]}
    assert settings["inpaint"]["dilate"] == 1 and settings["complete"]["warm"]
    # Init (warm, the default) and FT both continue from the base run's scene: --short-steps, not --complete-steps
    assert settings["complete"]["steps"] == 120 and cells[1]["settings"]["complete"]["steps"] == 120
    assert settings["versions"]["torch"] and settings["versions"]["engine"] and settings["gpu"] is None
    phases = cells[0]["phases"]  # where the cell's time went: its own phases inside the engine process's time
    assert phases["train"] >= phases["train_loop"] > 0
    assert phases["process"] > sum(phases[k] for k in ("load", "scene", "train", "score"))
    table = (tmp_path / "tables.md").read_text()
    assert "| Removed (unfilled) |" in table and "| Init-fsr[warm] |" in table and "**" in table
    flat, blur = (cells[0]["oracle_scores"][k]["m_psnr"] for k in ("flat", "blur"))
    assert blur > flat > 0 and "| Oracle: truth blurred 4 px |" in table  # the headroom beside the methods
    assert cells[0]["seconds"] == round(sum(cells[0]["stages"].values()) + cells[0]["complete_seconds"], 1)
    assert set(cells[0]["stages"]) == {"train", "remove", "holes", "inpaint-fsr"} and "commit" in cells[0]
    assert "Failed cells" in table and "LAMA_MODEL" in table
    stability = (tmp_path / "stability.md").read_text()
    assert "| Init-fsr[warm] | 1/1 |" in stability and "| Init-lama[warm] | 0/1 |" in stability
    assert "LAMA_MODEL" in stability
    svg = (tmp_path / "speed_accuracy.svg").read_text()
    assert svg.startswith("<svg") and svg.count("<circle") == 4  # 2 methods that finished x 2 panels
    chart = read_png(tmp_path / "speed_accuracy.png")  # the same items drawn by the engine
    assert chart.shape[:2] == (2 * (340 + 18 + 20), 2 * 920) and (chart != 255).any()  # one row, a legend line
    picture = read_png(tmp_path / "pictures" / f"{living_scene.name}.png")
    # region, effects, hole, GT, Init-fsr[warm], FT-fsr(3)[l1] for the tiny scene's 96 px wide views
    assert picture.shape[1] == 6 * 96
    timed = tmp_path / "work" / living_scene.name / "seed0" / "times"
    times = sorted(p.name for p in timed.iterdir() if json.loads(p.read_text())["ok"])
    assert len(times) == 6  # one process each: train, remove, holes, inpaint-fsr and the two cells' completions
    assert [json.loads(p.read_text())["ok"] for p in timed.glob("inpaint-lama.*")] == [False]  # its failure too
    # resumed, one after the other (the first ran as Ray tasks): finished cells and stages are not run again
    second = benchmark(living_scene, tmp_path, "--scheduler", "serial")
    assert second.returncode == 0, second.stderr[-2000:]
    assert (tmp_path / "tables.md").read_text() == table
    assert sorted(p.name for p in timed.iterdir() if json.loads(p.read_text())["ok"]) == times
    assert "2/4" in second.stdout and "tables:" in second.stdout
    report = benchmark(living_scene, tmp_path, "--report-only", seeds=("0", "1"))  # runs nothing for seed 1
    assert report.returncode == 0, report.stderr[-2000:]
    assert not (tmp_path / "work" / living_scene.name / "seed1").exists()
    table = (tmp_path / "tables.md").read_text()
    assert "| Init-fsr[warm] |" in table and "## Cells not run" in table and "seed 1 Init-fsr[warm]" in table
    assert "| Init-fsr[warm] | 1/2 |" in (tmp_path / "stability.md").read_text()


def test_each_kind_of_cell_makes_and_is_charged_the_stages_it_needs(living_scene: Path, tmp_path: Path, monkeypatch):
    """Direct's inpainting needs the removal only, but its warm completion reads the hole masks, so its cells make
    them too; the other cells' inpainting needs them first."""
    from benchmarks.matrix_stages import Stages

    monkeypatch.setenv("SPLATFILL_ENGINE_PYTHON", sys.executable)
    stages = Stages(living_scene, 0, tmp_path, argparse.Namespace(preset="tiny", max_gaussians=0, steps=100,
                                                                  device="cpu", dilate=1))
    stages.prepare("fsr", "input")
    assert stages.run.inpainted("fsr", "input").root.is_dir() and stages.run.removed.root.is_dir()
    assert stages.run.holes.root.is_dir()  # a warm Direct trains only what renders into the hole
    assert not stages.run.inpainted("fsr", "removed").root.exists()
    stages.prepare("fsr", "removed")
    assert stages.run.inpainted("fsr", "removed").root.is_dir()
    # each kind of cell is charged the stages it runs, every one of them timed
    assert set(stages.needs("input", "fsr")) == {"train", "remove", "holes", "inpaint-direct-fsr"}
    assert set(stages.needs("removed", "fsr")) == {"train", "remove", "holes", "inpaint-fsr"}
    assert all(s > 0 for s in stages.needs("removed", "fsr").values())


def test_a_stage_time_is_never_lost_or_silently_zero(tmp_path: Path, monkeypatch):
    """A stage that failed and ran again counts both processes; a stage on disk that no process timed is an error
    naming it, not 0 s."""
    from addon.engine_call import EngineError
    from benchmarks import matrix_stages
    from benchmarks.matrix_stages import MissingTime, Stages

    stages = Stages(tmp_path / "scene", 0, tmp_path, argparse.Namespace())
    outcomes = iter([EngineError("first try failed"), None, None])

    def engine(args):
        time.sleep(0.05)
        if (error := next(outcomes)) is not None:
            raise error

    monkeypatch.setattr(matrix_stages, "run_engine", engine)
    with pytest.raises(EngineError):
        stages.timed("holes", ["holes"])
    stages.timed("holes", ["holes"])
    assert stages.seconds("holes") >= 0.1 and len(list(stages.times_dir.glob("holes.*.json"))) == 2
    stages.timed("complete-Init-fsr[warm]", ["complete"])  # a cell's name, glob's brackets in it
    assert stages.seconds("complete-Init-fsr[warm]") >= 0.05
    with pytest.raises(MissingTime, match="'inpaint-fsr'"):
        stages.seconds("inpaint-fsr")


def test_cells_that_continue_from_the_base_run_take_the_short_steps_and_the_scratch_ones_the_complete_steps():
    """--complete-steps reaches only the cells that train a new scene from scratch (the matrix test above runs
    warm Init and FT, which take --short-steps)."""
    import argparse

    from benchmarks.matrix_stages import cell_method

    args = argparse.Namespace(short_steps=120, complete_steps=100, perceptual="l1")
    steps = {cell: cell_method(cell, args)[2] for cell in ("init", "reference", "direct", "ft3", "ftall",
                                                            "init-scratch", "reference-scratch", "direct-scratch",
                                                            "init-colmap")}
    assert steps == {"init": 120, "reference": 120, "direct": 120, "ft3": 120, "ftall": 120,
                     "init-scratch": 100, "reference-scratch": 100, "direct-scratch": 100, "init-colmap": 100}
    assert cell_method("init-scratch", args)[1]["warm"] is False and cell_method("init", args)[1]["warm"]


def test_the_benchmark_runs_the_shipped_defaults_unless_told_otherwise(tmp_path: Path, monkeypatch):
    """With no flags a cell is what a user gets from the CLI: FT's perceptual term is the method's default, and the
    inpainting is called without --dilate so InpaintConfig's default applies (the table once ran dilate 4 and
    ST-LPIPS while the CLI shipped 0 and LPIPS)."""
    from benchmarks import matrix as benchmark
    from benchmarks import matrix_stages as benchmark_stages
    from benchmarks.matrix_stages import Stages, cell_method
    from engine.complete.registry import get

    args = benchmark.build_parser().parse_args(["--scenes", "S", "--out", str(tmp_path)])
    default = {o.name: o.default for o in get("ft").options}["perceptual"]
    assert cell_method("ft3", args)[1]["perceptual"] == default
    calls = []
    monkeypatch.setattr(benchmark_stages, "run_engine", lambda a: calls.append(a))
    Stages(tmp_path / "scene", 0, tmp_path / "work", args).inpaint("telea", "removed")
    assert calls and "--dilate" not in calls[0]


def test_an_inpainting_task_shares_a_gpu_with_the_trainings_and_no_more_trainings_than_asked_share_one():
    """Ray packs tasks onto a GPU while their shares add up to at most one (in units of 1e-4)."""
    from benchmarks.matrix_ray import task_resources

    def units(kind: dict) -> int:
        return round(kind["num_gpus"] * 10_000)

    one = task_resources(2, trainings_per_gpu=1)
    train, inpaint = units(one["train"]), units(one["inpaint"])
    assert train + inpaint <= 10_000 and 2 * train > 10_000 and inpaint > 0
    assert task_resources(0) == {"train": {"num_cpus": 1}, "inpaint": {"num_cpus": 1}}
    two = units(task_resources(2)["train"])  # the default: two trainings and a sliver
    assert 2 * two + inpaint <= 10_000 and 3 * two > 10_000


def test_model_inpainters_take_a_gpu_of_their_own_and_the_light_ones_share():
    from benchmarks.matrix_ray import light

    assert light("telea") and light("exemplar") and light("fsr")
    assert not light("lama") and not light("diffusion") and not light("no-such-inpainter")
