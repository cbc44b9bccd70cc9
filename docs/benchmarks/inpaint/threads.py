"""Exemplar on synthetic 640x480 views, one view at a time against N views at once in threads, through the engine's
own view loop (engine.inpaint.run._each_view); the fills must be identical. Issue 18: the direct baseline's exemplar
inpainting (100 views, one at a time on a GPU) took 164 s of a 960 s matrix in run 4.

    PYTHONPATH=. python docs/benchmarks/inpaint/threads.py [VIEWS] [WORKERS...]   (default 16 views, workers 1 8)

Prints one line per worker count: seconds, seconds a view, speed-up over the first, identical or not, and the device.
"""

from __future__ import annotations

import sys
import time

import numpy as np
import torch

from engine.inpaint.inpainters.exemplar import exemplar_fill
from engine.inpaint.run import _each_view


def _view(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Wood-like stripes with noise, a 90x100 px hole at a random place (the size of run 4's direct regions)."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:480, 0:640]
    stripes = 0.5 + 0.5 * np.sin(cols / (6 + seed % 5) + rows / 40)
    image = np.stack([150 + 80 * stripes, 100 + 60 * stripes, 60 + 40 * stripes], -1)
    image = np.clip(image + rng.normal(0, 8, image.shape), 0, 255).astype(np.uint8)
    mask = np.zeros((480, 640), bool)
    r, c = rng.integers(60, 330), rng.integers(60, 480)
    mask[r:r + 90, c:c + 100] = True
    return image, mask


def main() -> None:
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    workers = [int(w) for w in sys.argv[2:]] or [1, 8]
    views = [_view(i) for i in range(count)]
    fills, first = {}, None
    for n in workers:
        start = time.perf_counter()
        out = dict(_each_view(lambda i: exemplar_fill(*views[i]), count, n))
        seconds = time.perf_counter() - start
        fills[n] = out
        first = first or seconds
        same = all(np.array_equal(out[i], fills[workers[0]][i]) for i in range(count))
        device = torch.cuda.get_device_name() if torch.cuda.is_available() else "cpu"
        print(f"workers {n}: {seconds:.1f} s, {seconds / count:.2f} s a view, {first / seconds:.2f}x, "
              f"{'identical' if same else 'DIFFERENT'}, {device}", flush=True)


if __name__ == "__main__":
    main()
