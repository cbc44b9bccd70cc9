"""Running the engine (`python -m engine ...`) from Blender-side code, in its own Python.

Blender's Python never imports torch: the engine runs as a subprocess of the environment the user
points at (the preferences' engine Python, else SPLATFILL_ENGINE_PYTHON, else the repo's .venv) and
reports progress as JSON lines. Settings and secrets the engine needs (weight paths, the Gemini key) go
into that subprocess's own environment (`env`), never into Blender's os.environ, the arguments (which
the process list shows) or a log.
run_engine is the blocking form used by scripts and `blender -b`; the add-on's modal operators poll an
EngineJob instead, so the UI never waits on the engine.
"""

from __future__ import annotations

import json
import os
import queue
import signal
import subprocess
import sys
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent


class EngineError(RuntimeError):
    """The engine failed; the message is its one-line error."""


def stop_session(proc: subprocess.Popen) -> None:
    """SIGTERM to a process started with start_new_session=True and everything it started, if still running."""
    if proc.poll() is None:
        if hasattr(os, "killpg"):
            os.killpg(proc.pid, signal.SIGTERM)
        else:
            proc.terminate()


def engine_python(configured: str = "") -> Path:
    """The engine environment's interpreter (`configured`, else SPLATFILL_ENGINE_PYTHON, else the repo's
    .venv), or a clear error saying how to make one."""
    configured = configured or os.environ.get("SPLATFILL_ENGINE_PYTHON", "")
    default = REPO_ROOT / ".venv" / ("Scripts/python.exe" if sys.platform == "win32" else "bin/python")
    path = Path(configured) if configured else default
    if not path.is_file():
        raise EngineError(
            f"engine Python {path} not found: run `make setup` in {REPO_ROOT} or set SPLATFILL_ENGINE_PYTHON"
        )
    return path


def engine_env(extra: dict[str, str] | None = None) -> dict[str, str]:
    """The subprocess's environment: Blender's, plus `extra` (settings and secrets for this engine only)."""
    env = dict(os.environ, **(extra or {}), SPLATFILL_PROGRESS="json", PYTHONUNBUFFERED="1")
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO_ROOT), env.get("PYTHONPATH")]))
    return env


class EngineJob:
    """One engine subprocess in a session of its own (so a cancel reaches its workers too); a reader thread
    queues its JSON lines, which the caller drains with poll() from its own thread (Blender's main thread,
    which alone may touch bpy)."""

    def __init__(self, args: list[str], python: str = "", env: dict[str, str] | None = None) -> None:
        self.errors = tempfile.TemporaryFile(mode="w+")  # a file, so a chatty stderr cannot block the pipe
        self.proc = subprocess.Popen([str(engine_python(python)), "-m", "engine", *args], stdout=subprocess.PIPE,
                                     stderr=self.errors, text=True, env=engine_env(env), start_new_session=True)
        self.lines: queue.Queue[dict] = queue.Queue()
        self.records: list[dict] = []
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            try:
                self.lines.put(json.loads(line))
            except json.JSONDecodeError:
                continue  # stray prints from libraries are not part of the stream

    def poll(self, timeout: float = 0.0) -> list[dict]:
        """The records that arrived since the last call (waiting up to `timeout` s for the first)."""
        new = []
        try:
            new.append(self.lines.get(timeout=timeout) if timeout else self.lines.get_nowait())
            while True:
                new.append(self.lines.get_nowait())
        except queue.Empty:
            pass
        self.records += new
        return new

    @property
    def finished(self) -> bool:
        return self.proc.poll() is not None and not self.reader.is_alive() and self.lines.empty()

    def cancel(self) -> None:
        """SIGTERM to the engine's process group: training checkpoints and stops; other stages stop before
        their output folder is renamed into place, so nothing half-written is left."""
        stop_session(self.proc)

    def result(self) -> list[dict]:
        """Every record, once the process ended; EngineError with its one-line message if it failed."""
        self.proc.wait()
        self.reader.join()
        self.poll()
        self.errors.seek(0)
        stderr = self.errors.read()
        self.errors.close()
        if self.proc.returncode != 0:
            lines = [ln for ln in stderr.strip().splitlines() if ln.strip()]
            raise EngineError(lines[-1] if lines else f"engine exited with status {self.proc.returncode}")
        return self.records


def run_engine(args: list[str], on_progress: Callable[[dict], None] | None = None, python: str = "",
               env: dict[str, str] | None = None) -> list[dict]:
    """Run `python -m engine *args` to completion (scripts, and Blender in the background, where timers
    never fire); returns its JSON records, raises EngineError on failure."""
    job = EngineJob(args, python, env)
    while not job.finished:
        for record in job.poll(timeout=0.1):
            if on_progress is not None:
                on_progress(record)
    return job.result()


_PLUGINS: dict = {}


def engine_plugins(python: str = "") -> dict:
    """The engine's inpainters and completion methods (`python -m engine plugins`): what the add-on's menus
    offer. Asked once per session; the engine's registries are the only list."""
    if not _PLUGINS:
        record = next((r for r in run_engine(["plugins"], python=python) if r.get("event") == "plugins"), None)
        if record is None:
            raise EngineError("the engine did not list its plug-ins: update the engine (make setup)")
        _PLUGINS.update(record)
    return _PLUGINS
