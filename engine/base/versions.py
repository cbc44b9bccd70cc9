"""What a result was made with: the code's commit, the engine's, Python's, torch's and gsplat's versions and the GPU,
for the records every training run and benchmark cell keep (a number without its setting cannot be compared). torch
is imported where it is used, so that the Blender environment's measurement tools read the commit here too."""

from __future__ import annotations

import functools
import importlib.metadata
import os
import platform
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


@functools.cache
def code_commit() -> str | None:
    """The checkout's commit (short hash, "+dirty" with uncommitted changes to tracked files outside docs/, where
    records are written). A copy of the tree without .git (a GPU machine's) names it in SPLATFILL_COMMIT, which
    benchmarks/gpu.sh passes on."""
    if os.environ.get("SPLATFILL_COMMIT"):
        return os.environ["SPLATFILL_COMMIT"]
    try:
        head = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=no", "--", ".",
                                ":!docs"],
                               capture_output=True, text=True, timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return head + ("+dirty" if dirty else "")


def versions() -> dict[str, str | None]:
    import torch

    from engine import __version__

    try:
        gsplat = importlib.metadata.version("gsplat")
    except importlib.metadata.PackageNotFoundError:
        gsplat = None
    return {"engine": __version__, "commit": code_commit(), "python": platform.python_version(),
            "torch": torch.__version__, "cuda": torch.version.cuda, "gsplat": gsplat}


def gpu_name(device) -> str | None:
    """The CUDA device's name, None on the CPU (`device`: a torch.device)."""
    import torch

    return torch.cuda.get_device_name(device) if device.type == "cuda" else None
