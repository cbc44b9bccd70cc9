"""Exemplar's patch search as a correlation of the window (engine.inpaint.inpainters.exemplar._SourceSearch)
against the unrolled source matrix it replaced, on a scene's real object regions (each view's target mask grown by
3 px, about the direct baseline's regions), through the engine's own view loop (engine.inpaint.run._each_view).

    PYTHONPATH=. python benchmarks/inpaint_speed.py SCENE [VIEWS] [WORKERS,...] [--old=OLD.py]

OLD.py is the previous exemplar.py (`git show b0eaac9:engine/inpaint/inpainters/exemplar.py`, saved outside the
tree): one view at a time through it, then the new search in processes, once for each count in WORKERS (1: one
at a time; default 1,8), and whether the fills are identical to the old ones. The search always runs on the CPU.
"""

from __future__ import annotations

import importlib.util
import os
import sys
import time
from pathlib import Path

import cv2
import numpy as np

from engine.formats.layout import SceneLayout
from engine.inpaint.inpainters.exemplar import exemplar_fill
from engine.inpaint.run import _each_view
from engine.io.image_io import read_png


def _views(scene: Path, count: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """`count` views spread over the scene: (image, target region grown by 3 px)."""
    layout = SceneLayout(scene)
    names = sorted(p.name for p in layout.images.iterdir())
    names = names[::max(len(names) // count, 1)][:count]
    out = []
    for name in names:
        target = read_png(layout.masks / name, kind="mask") == 1
        region = cv2.dilate(target.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
        out.append((read_png(layout.images / name), region))
    return out


def _timed(views, workers: int, fill=exemplar_fill) -> tuple[float, dict[int, np.ndarray]]:
    """Seconds for `fill` over every view, one at a time or in `workers` processes, and the fills by view."""
    start = time.perf_counter()
    fills = dict(_each_view(fill, views, workers, "processes" if workers > 1 else ""))
    return time.perf_counter() - start, fills


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
