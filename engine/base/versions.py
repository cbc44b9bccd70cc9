"""What a result was made with: the engine's, Python's, torch's and gsplat's versions and the GPU, for the records
every training run and benchmark cell keep (a number without its setting cannot be compared)."""

from __future__ import annotations

import importlib.metadata
import platform

import torch


def versions() -> dict[str, str | None]:
    from engine import __version__

    try:
        gsplat = importlib.metadata.version("gsplat")
    except importlib.metadata.PackageNotFoundError:
        gsplat = None
    return {"engine": __version__, "python": platform.python_version(), "torch": torch.__version__,
            "cuda": torch.version.cuda, "gsplat": gsplat}


def gpu_name(device: torch.device) -> str | None:
    return torch.cuda.get_device_name(device) if device.type == "cuda" else None
