"""Where model weights users already have are looked for: a given path, an environment variable, and the
file name in torch's hub cache ($TORCH_HOME/hub/checkpoints/), where torchvision and pytorch-fid keep them.
Nothing is downloaded."""

from __future__ import annotations

import os
from pathlib import Path

import torch

from engine.base.errors import InputError


def find_weights(given: str, env: str, file_name: str, what: str) -> Path:
    """The first existing file among `given`, $`env` and the hub cache's `file_name`, else a one-line error."""
    candidates = [given, os.environ.get(env, ""), str(Path(torch.hub.get_dir()) / "checkpoints" / file_name)]
    for candidate in candidates:
        if candidate and Path(candidate).is_file():
            return Path(candidate)
    raise InputError(f"{what} {file_name} not found (looked at {', '.join(c for c in candidates if c)}): "
                     f"pass its path or set {env}")
