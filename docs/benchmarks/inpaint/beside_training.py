"""Exemplar over a scene's real object regions, one view at a time against N views in processes, through the
engine's own view loop (engine.inpaint.run._each_view), with whatever else runs on the GPU meanwhile: run 8 found
processes 1.07-1.09x alone, and Direct's inpainting beside two trainings 217 s in processes against 309-329 s one
at a time in run 7, on other hosts' load. `beside_training.sh` runs this beside two trainings on one GPU.

    PYTHONPATH=. python docs/benchmarks/inpaint/beside_training.py SCENE [VIEWS] [WORKERS...]

SCENE is a generated scene folder; each region is its target's mask (id 1) grown by 3 px, about the direct
baseline's regions. Default 16 views, workers 8. The modes alternate (one at a time, processes, one at a time
again), so a change in the load between them shows as two different one-at-a-time times.
"""

from __future__ import annotations

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


def _timed(views, workers: int, fill=exemplar_fill) -> tuple[float, dict[int, np.ndarray]]:
    """Seconds for `fill` over every view, one at a time or in `workers` processes, and the fills by view."""
    start = time.perf_counter()
    fills = dict(_each_view(fill, views, workers, "processes" if workers > 1 else ""))
    return time.perf_counter() - start, fills


def main() -> None:
    scene = Path(sys.argv[1])
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 16
    workers = [int(w) for w in sys.argv[3:]] or [8]
    views = _views(scene, count)
    device = torch.cuda.get_device_name() if torch.cuda.is_available() else "cpu"
    print(f"{len(views)} views, {np.mean([r.sum() for _, r in views]):.0f} px a region, {device}", flush=True)
    exemplar_fill(*views[0])  # CUDA's first-call set-up, outside the timings
    one, first = _timed(views, 1)
    print(f"one at a time: {one / len(views):.2f} s a view", flush=True)
    for n in workers:
        seconds, fills = _timed(views, n)
        same = all(np.array_equal(fills[i], first[i]) for i in first)
        print(f"{n} processes: {seconds / len(views):.2f} s a view (their start included), {one / seconds:.2f}x, "
              f"{'identical' if same else 'DIFFERENT'}", flush=True)
    again, _ = _timed(views, 1)
    print(f"one at a time again: {again / len(views):.2f} s a view", flush=True)


if __name__ == "__main__":
    main()
