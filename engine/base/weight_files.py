"""Where model weights users already have are looked for: a given path, an environment variable, the file
name in torch's hub cache ($TORCH_HOME/hub/checkpoints/), where torchvision and pytorch-fid keep them, and the
weights `make setup` took from registry packages (the repository's .weights/, or $SPLATFILL_WEIGHTS).
Nothing is downloaded at run time."""

from __future__ import annotations

import os
from pathlib import Path

import torch

from engine.base.errors import InputError

WEIGHTS_ENV = "SPLATFILL_WEIGHTS"


def setup_weights_dir() -> Path:
    """Where the set-up puts weights it took from registry packages: $SPLATFILL_WEIGHTS, else .weights/ in the
    repository."""
    return Path(os.environ.get(WEIGHTS_ENV) or Path(__file__).resolve().parents[2] / ".weights")


def find_weights(given: str, env: str, file_name: str, what: str, setup_name: str = "") -> Path:
    """The first existing file among `given`, $`env`, the hub cache's `file_name` and the set-up's
    `setup_name`, else a one-line error."""
    candidates = [given, os.environ.get(env, ""), str(Path(torch.hub.get_dir()) / "checkpoints" / file_name),
                  str(setup_weights_dir() / setup_name) if setup_name else ""]
    for candidate in candidates:
        if candidate and Path(candidate).is_file():
            return Path(candidate)
    raise InputError(f"{what} {file_name} not found (looked at {', '.join(c for c in candidates if c)}): "
                     f"pass its path or set {env}")
