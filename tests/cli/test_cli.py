"""The command line's contract: every bad input is one line on stderr and status 2, never a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("args, says", [
    (["train", "--scene", "SCENE", "--out", "OUT", "--preset", "nonsense"], "unknown preset 'nonsense': choose from"),
    (["complete", "--run", "RUN", "--method", "ft", "--recolmap"], "--recolmap is not an option of --method ft"),
])
def test_bad_options_end_in_one_line_and_status_2(tmp_path: Path, args: list[str], says: str):
    args = [a.replace("SCENE", str(tmp_path / "scene")).replace("OUT", str(tmp_path / "out"))
            .replace("RUN", str(tmp_path / "run")) for a in args]
    (tmp_path / "scene").mkdir()
    proc = subprocess.run([sys.executable, "-m", "engine", *args], capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip().count("\n") == 0 and says in proc.stderr, proc.stderr


@pytest.mark.fast
def test_every_setting_of_every_stage_says_what_it_means_in_help():
    """--help shows each config field's comment; a field without one would show a bare default."""
    from engine.base.config_cli import field_help
    from engine.complete.run import CompleteConfig
    from engine.convert.import_splat import ImportConfig
    from engine.edit.holes import HoleConfig
    from engine.edit.removal import RemovalConfig
    from engine.inpaint.run import InpaintConfig
    from engine.metrics.scores import ScoreConfig
    from engine.pictures.turntable import TurntableConfig
    from engine.segment.run import SegmentConfig
    from engine.train.config import TrainConfig

    configs = (TrainConfig, RemovalConfig, HoleConfig, InpaintConfig, CompleteConfig, SegmentConfig, ImportConfig,
               TurntableConfig, ScoreConfig)
    bare = {c.__name__: [n for n, text in field_help(c).items() if not text] for c in configs}
    assert not {k: v for k, v in bare.items() if v}, f"fields without a one-line meaning: {bare}"
    assert "every Nth step" in subprocess.run([sys.executable, "-m", "engine", "train", "--help"], cwd=REPO,
                                              capture_output=True, text=True).stdout
