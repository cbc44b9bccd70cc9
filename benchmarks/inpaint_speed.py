"""Exemplar's patch search as a correlation of the window (engine.inpaint.inpainters.exemplar._SourceSearch)
against the unrolled source matrix it replaced, on a scene's real object regions (beside_training.py's views).

    PYTHONPATH=. python benchmarks/inpaint_speed.py SCENE [VIEWS] [WORKERS,...] [--old=OLD.py]

OLD.py is the previous exemplar.py (`git show b0eaac9:engine/inpaint/inpainters/exemplar.py`, saved outside the
tree): one view at a time through it, then the new search in processes, once for each count in WORKERS (1: one
at a time; default 1,8), and whether the fills are identical to the old ones. d1a4076's first form searched on the
GPU where there was one (run 10's first call measured both; CUDA_VISIBLE_DEVICES= made it use the CPU); the
search now always runs on the CPU.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from beside_training import _timed, _views  # noqa: E402

from engine.inpaint.inpainters.exemplar import exemplar_fill  # noqa: E402


def _load(path: str):
    spec = importlib.util.spec_from_file_location("exemplar_old", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.exemplar_fill


def _identical(fills: dict[int, np.ndarray], reference: dict[int, np.ndarray], views) -> float:
    """The share of the regions' pixels that came out the same as the old search's."""
    return float(np.mean([(fills[i] == reference[i]).all(-1)[views[i][1]].mean() for i in fills]))


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--old")]
    old = next((a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--old=")), "")
    scene, count = Path(args[0]), int(args[1]) if len(args) > 1 else 16
    workers = [int(n) for n in (args[2] if len(args) > 2 else "1,8").split(",")]
    views = _views(scene, count)
    print(f"{len(views)} views, {np.mean([r.sum() for _, r in views]):.0f} px a region, {os.cpu_count()} cores",
          flush=True)
    exemplar_fill(*views[0])  # the first call's set-up, outside the timings
    reference = None
    if old:
        seconds, reference = _timed(views, 1, _load(old))
        print(f"old search, one at a time: {seconds / len(views):.2f} s a view", flush=True)
    for n in workers:
        seconds, fills = _timed(views, n)
        same = "" if reference is None else f", identical pixels {_identical(fills, reference, views):.4f}"
        print(f"new search, {n} at once: {seconds / len(views):.2f} s a view{same}", flush=True)


if __name__ == "__main__":
    main()
