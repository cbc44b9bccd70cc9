"""Exemplar's patch search as one correlation of the window (session 22) against the matrix of every source
patch it replaced, on a scene's real object regions: seconds a view, one view at a time, and the new search in N
processes through the engine's own view loop (engine.inpaint.run._each_view); the fills must be identical.

    git show 39ece91:engine/inpaint/inpainters/exemplar.py > /tmp/exemplar_old.py
    PYTHONPATH=. python docs/benchmarks/inpaint/exemplar_search.py SCENE /tmp/exemplar_old.py [VIEWS] [WORKERS...]

SCENE is a generated scene folder (images/, masks/, objects in scene.json's generator order: the target is id 1);
each region is the target's mask grown by 3 px, as the direct baseline's regions are about (the removed object
and its contact). Default 8 views, workers 4.
"""

from __future__ import annotations

import importlib.util
import sys
import time
from pathlib import Path

import cv2
import numpy as np
import torch

from engine.inpaint.inpainters.exemplar import exemplar_fill
from engine.inpaint.run import _each_view
from engine.io.image_io import read_png


def _views(scene: Path, count: int) -> list[tuple[np.ndarray, np.ndarray]]:
    names = sorted(p.name for p in (scene / "images").iterdir())
    names = names[::max(len(names) // count, 1)][:count]
    out = []
    for name in names:
        target = read_png(scene / "masks" / name, kind="mask") == 1
        region = cv2.dilate(target.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
        out.append((read_png(scene / "images" / name), region))
    return out


def _timed(fill, views) -> tuple[float, list[np.ndarray]]:
    start = time.perf_counter()
    fills = [fill(*view) for view in views]
    return time.perf_counter() - start, fills


def main() -> None:
    scene, old_path = Path(sys.argv[1]), sys.argv[2]
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 8
    workers = [int(w) for w in sys.argv[4:]] or [4]
    spec = importlib.util.spec_from_file_location("exemplar_old", old_path)
    old = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(old)
    views = _views(scene, count)
    device = torch.cuda.get_device_name() if torch.cuda.is_available() else "cpu"
    print(f"{len(views)} views, {np.mean([r.sum() for _, r in views]):.0f} px a region, {device}", flush=True)
    _timed(exemplar_fill, views[:1])  # CUDA's and the convolution's first-call set-up, outside the timings
    _timed(old.exemplar_fill, views[:1])
    new_s, new = _timed(exemplar_fill, views)
    old_s, before = _timed(old.exemplar_fill, views)
    same = all(np.array_equal(a, b) for a, b in zip(new, before, strict=True))
    count = len(views)
    print(f"one at a time: correlation {new_s / count:.2f} s a view, matrix {old_s / count:.2f} s a view, "
          f"{old_s / new_s:.2f}x, {'identical' if same else 'DIFFERENT'}", flush=True)
    for n in workers:
        start = time.perf_counter()
        fills = dict(_each_view(exemplar_fill, views, n, "processes"))
        seconds = time.perf_counter() - start
        same = all(np.array_equal(fills[i], new[i]) for i in range(count))
        print(f"{n} processes: {seconds / count:.2f} s a view (start included), {new_s / seconds:.2f}x over one at a "
              f"time, {'identical' if same else 'DIFFERENT'}", flush=True)


if __name__ == "__main__":
    main()
