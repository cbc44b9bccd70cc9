"""Progress for long work: JSON lines on stdout for the Blender add-on, a bar for people.

Each JSON line is one object: {"stage", "step", "total", "seconds", ...extra}. When stdout is a terminal
(and SPLATFILL_PROGRESS is not "json") a tqdm bar on stderr is shown instead.
"""

from __future__ import annotations

import json
import os
import sys
import time

from tqdm import tqdm


def json_mode() -> bool:
    """JSON lines when asked (the add-on sets SPLATFILL_PROGRESS=json) or when nobody watches a terminal."""
    return os.environ.get("SPLATFILL_PROGRESS") == "json" or not sys.stdout.isatty()


class Progress:
    """Reports `step` of `total` for one named stage."""

    def __init__(self, stage: str, total: int) -> None:
        self.stage, self.total, self.start = stage, total, time.monotonic()
        self.json = json_mode()
        self.bar = None if self.json else tqdm(total=total, desc=stage, file=sys.stderr, leave=False)

    def update(self, step: int, **extra: float | int | str) -> None:
        if self.bar is not None:
            self.bar.n = step
            self.bar.set_postfix(extra, refresh=True)
            return
        record = {"stage": self.stage, "step": step, "total": self.total,
                  "seconds": round(time.monotonic() - self.start, 3), **extra}
        _line(json.dumps(record))

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def say(text: str) -> None:
    """A line for people: stdout on a terminal; stderr when stdout is the add-on's JSON-lines stream."""
    print(text, file=sys.stderr if json_mode() else sys.stdout, flush=True)


def emit(event: str, **fields: object) -> None:
    """One non-progress JSON line (e.g. {"event": "done", "out": ...}) for the add-on; silent on a TTY."""
    if json_mode():
        _line(json.dumps({"event": event, **fields}))


def _line(text: str) -> None:
    """One JSON line on stdout; once its reader has gone (Blender closed, a `| head`), none. Why: the work goes on
    to write its outputs (a cancel its checkpoint) instead of ending as an internal error at its next line."""
    try:
        print(text, flush=True)
    except BrokenPipeError:
        devnull = os.open(os.devnull, os.O_WRONLY)  # the buffered line and every later one go nowhere
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
