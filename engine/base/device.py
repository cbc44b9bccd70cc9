"""Which torch device a command runs on: one rule for every stage, so `--device` means the same everywhere."""

from __future__ import annotations

import torch

from engine.base.errors import InputError


def pick_device(name: str) -> torch.device:
    """`auto` is the GPU when torch sees one, else the CPU; `cuda` without a GPU is a clear error."""
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    if name == "cuda" and not torch.cuda.is_available():
        raise InputError("--device cuda but torch sees no GPU: install a CUDA build of torch or use --device cpu")
    try:
        return torch.device(name)
    except RuntimeError as exc:
        raise InputError(f"unknown --device {name!r}: use auto, cpu, cuda or cuda:N") from exc
