"""How far to grow the hole masks before inpainting, on a finished removal: each test view's removed render
filled in its `holes` mask grown by D px, m-PSNR against the truth (gt/) in the true hole (holes/), beside the
unfilled render's. The 2D stage alone, on the 3D pipeline's own renders (a removal's leftovers at the hole's
border included, which is what growing is for); what a completion adds on top is the held-out table's.

    PYTHONPATH=. python benchmarks/grow_sweep.py RUN... [--grow 0 1 3 6 13] [--inpainter telea] [--json OUT]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from engine.formats.layout import RunLayout
from engine.inpaint.registry import create
from engine.io.image_io import read_png
from engine.io.masks import dilate
from engine.metrics.image_metrics import psnr_from_mse
from engine.train.trained_run import load_run_scene


def masked_psnr(image: np.ndarray, truth: np.ndarray, mask: np.ndarray) -> float:
    return psnr_from_mse(float((((image[mask].astype(float) - truth[mask]) / 255.0) ** 2).mean()))


def sweep(run: Path, grows: list[int], inpainter: str) -> dict:
    """Per grow (and 'unfilled'), the mean over test views with a true hole of m-PSNR in it."""
    scene, layout = load_run_scene(run), RunLayout(run)
    fill = create(inpainter)
    scores: dict[str, list[float]] = {"unfilled": [], **{f"D={d}": [] for d in grows}}
    for i in scene.test:
        truth_hole = scene.holes.get(i)
        if truth_hole is None or truth_hole.sum() < 20 or i not in scene.gt_images:
            continue
        name, truth = scene.cameras[i].name, scene.gt_images[i]
        removed = read_png(layout.removed.images / name)
        hole = read_png(layout.holes.mask(name), kind="mask") > 0
        scores["unfilled"].append(masked_psnr(removed, truth, truth_hole))
        for d in grows:
            scores[f"D={d}"].append(masked_psnr(fill.inpaint(removed, dilate(hole, d), "rgb"), truth, truth_hole))
    return {k: round(float(np.mean(v)), 3) for k, v in scores.items() if v} | {"views": len(scores["unfilled"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path)
    parser.add_argument("--grow", nargs="+", type=int, default=[0, 1, 3, 6, 13])
    parser.add_argument("--inpainter", default="telea")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    table = {}
    for run in args.runs:
        table[str(run)] = sweep(run, args.grow, args.inpainter)
        print(run, table[str(run)], flush=True)
    if args.json:
        args.json.write_text(json.dumps({"inpainter": args.inpainter, "runs": table}, indent=1))


if __name__ == "__main__":
    main()
