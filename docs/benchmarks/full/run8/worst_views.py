"""Per test view: PSNR of a base run's renders against images/, over all pixels and the seen ones (unseen/), the gap
below the mean, the share of the error in the worst 1% of pixels, and the worst 40 px block (row, col) against the
mean error: whether a worst view is one defect (a floater: a block far above the mean) or spread.

    python docs/benchmarks/full/run8/worst_views.py SCENE RENDERS   (RENDERS: `engine render` of the base run)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from engine.io.image_io import read_png
from engine.metrics.image_metrics import psnr_from_mse

BLOCK = 40  # px


def _row(scene: Path, render: Path) -> tuple[str, float, float, float, tuple[int, int], float]:
    rendered = read_png(render).astype(float) / 255
    seen_image = read_png(scene / "images" / render.name).astype(float) / 255
    err = ((rendered - seen_image) ** 2).mean(-1)
    unseen_png = scene / "unseen" / render.name
    unseen = read_png(unseen_png, kind="mask") > 0 if unseen_png.is_file() else np.zeros(err.shape, bool)
    ranked = np.sort(err.ravel())[::-1]
    top = ranked[: ranked.size // 100].sum() / ranked.sum()
    h, w = (n // BLOCK * BLOCK for n in err.shape)
    blocks = err[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).mean((1, 3))
    worst = np.unravel_index(blocks.argmax(), blocks.shape)
    return (render.name, psnr_from_mse(err.mean()), psnr_from_mse(err[~unseen].mean()), top,
            (int(worst[0]), int(worst[1])), blocks.max() / err.mean())


def main() -> None:
    scene, renders = Path(sys.argv[1]), Path(sys.argv[2])
    rows = [_row(scene, render) for render in sorted(renders.glob("*.png"))]
    mean = np.mean([row[1] for row in rows])
    for name, psnr, seen, top, block, ratio in rows:
        print(f"{name} psnr {psnr:.2f} seen {seen:.2f} gap {mean - psnr:.2f} top 1% share {top:.2f} "
              f"worst {BLOCK} px block {block} x{ratio:.1f} the mean")


if __name__ == "__main__":
    main()
