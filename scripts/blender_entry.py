"""Shared start-up for scripts that run both as `blender -b -P script.py -- ARGS` and `python script.py ARGS`."""

from __future__ import annotations

import sys
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent


def script_args(argv: list[str] | None = None) -> list[str]:
    """The script's own arguments: those after `--` under Blender, else everything after the script."""
    argv = sys.argv if argv is None else argv
    return argv[argv.index("--") + 1:] if "--" in argv else argv[1:]


def add_repo_to_path() -> None:
    """Make `addon`, `scripts.scenegen` etc. importable however the script was started."""
    for path in (REPO_ROOT, REPO_ROOT / "scripts"):
        if str(path) not in sys.path:
            sys.path.insert(0, str(path))
