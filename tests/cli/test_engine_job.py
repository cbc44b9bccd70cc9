"""The add-on's engine jobs (addon/engine_call.py), which Blender's modal operators poll: progress arrives
while the engine runs, Esc's cancel stops training with a checkpoint, and failures come back as one line."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

from addon.engine_call import EngineError, EngineJob
from tests.conftest import REPO


@pytest.fixture
def engine_here(monkeypatch):
    monkeypatch.setenv("SPLATFILL_ENGINE_PYTHON", sys.executable)


def test_a_cancelled_training_job_saves_a_checkpoint_and_says_how_to_resume(living_scene: Path, tmp_path: Path,
                                                                           engine_here):
    job = EngineJob(["train", "--scene", str(living_scene), "--out", str(tmp_path / "run"), "--preset", "tiny",
                     "--device", "cpu", "--steps", "5000", "--log-every", "2"])
    deadline = time.monotonic() + 300
    while not any(r.get("stage") == "train" for r in job.records):  # what the modal timer does, every 0.2 s
        assert not job.finished and time.monotonic() < deadline
        job.poll(timeout=0.2)
    job.cancel()  # Esc
    with pytest.raises(EngineError, match="--resume"):
        job.result()
    cancelled = next(r for r in job.records if r.get("event") == "cancelled")
    assert Path(cancelled["checkpoint"]).is_file()


def test_a_failing_job_reports_the_engines_one_line_error(tmp_path: Path, engine_here):
    job = EngineJob(["remove", "--run", str(tmp_path / "nothing"), "--object", "plush"])
    with pytest.raises(EngineError, match="nothing"):
        job.result()
    assert job.finished


def test_a_job_whose_reader_goes_away_still_writes_its_outputs(living_scene: Path, tmp_path: Path):
    """Blender closed (or a `| head`) while the engine runs: its progress lines have nowhere to go, and the
    training still ends with its point cloud and metrics, not as an internal error."""
    run = tmp_path / "run"
    proc = subprocess.Popen([sys.executable, "-m", "engine", "train", "--scene", str(living_scene), "--out", str(run),
                             "--preset", "tiny", "--device", "cpu", "--steps", "30", "--log-every", "1"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=REPO)
    assert proc.stdout is not None
    proc.stdout.readline()  # it has started talking
    proc.stdout.close()  # and nobody listens any more
    _, errors = proc.communicate(timeout=600)
    assert proc.returncode == 0, errors[-800:]
    assert (run / "point_cloud.ply").is_file() and (run / "metrics.json").is_file()
