"""The command line's contract: every bad input is one line on stderr and status 2, never a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent


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
