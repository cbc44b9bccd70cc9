"""Running the engine (`python -m engine ...`) from Blender-side code, in its own Python.

Blender's Python never imports torch: the engine runs as a subprocess of the environment the user
points at (SPLATFILL_ENGINE_PYTHON, default the repo's .venv) and reports progress as JSON lines.
This is the blocking form used by scripts and `blender -b`; the add-on's modal operators wrap it later.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent


class EngineError(RuntimeError):
    """The engine failed; the message is its one-line error."""


def engine_python() -> Path:
    """The engine environment's interpreter, or a clear error saying how to make one."""
    configured = os.environ.get("SPLATFILL_ENGINE_PYTHON")
    default = REPO_ROOT / ".venv" / ("Scripts/python.exe" if sys.platform == "win32" else "bin/python")
    path = Path(configured) if configured else default
    if not path.is_file():
        raise EngineError(
            f"engine Python {path} not found: run `make setup` in {REPO_ROOT} or set SPLATFILL_ENGINE_PYTHON"
        )
    return path


def run_engine(args: list[str], on_progress: Callable[[dict], None] | None = None) -> list[dict]:
    """Run `python -m engine *args` to completion; returns its JSON records, raises EngineError on failure."""
    env = dict(os.environ, SPLATFILL_PROGRESS="json", PYTHONUNBUFFERED="1")
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO_ROOT), env.get("PYTHONPATH")]))
    records = []
    with tempfile.TemporaryFile(mode="w+") as errors:  # a file, so a chatty stderr cannot block the pipe
        proc = subprocess.Popen([str(engine_python()), "-m", "engine", *args], stdout=subprocess.PIPE,
                                stderr=errors, text=True, env=env)
        assert proc.stdout is not None
        for line in proc.stdout:
            try:
                record = json.loads(line)
            except json.JSONDecodeError:
                continue  # stray prints from libraries are not part of the stream
            records.append(record)
            if on_progress is not None:
                on_progress(record)
        proc.wait()
        errors.seek(0)
        stderr = errors.read()
    if proc.returncode != 0:
        lines = [ln for ln in stderr.strip().splitlines() if ln.strip()]
        raise EngineError(lines[-1] if lines else f"engine exited with status {proc.returncode}")
    return records
