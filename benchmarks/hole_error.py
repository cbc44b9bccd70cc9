"""Where the error inside the true hole lies, per test view: m-PSNR of each set of renders against gt/, the part
of it that is colour bias (the render's mean over the hole against gt/'s) and what it would be with that bias
removed, beside two oracles that bound what a fill can reach without knowing the texture: gt/'s own mean over
the hole (a flat fill of the right colour) and gt/ blurred (the texture's coarse shape only). With --picture, the
holes' crops side by side (gt/, then each set), magnified. With --resolution N (a run trained at `--resolution N`),
the scene is read as training read it: its copy at 1/N of the size (engine.capture.downscale), so a tiny CPU run is
scored too.

    PYTHONPATH=. python benchmarks/hole_error.py SCENE NAME=DIR... [--picture OUT.png] [--resolution N]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import cv2
import numpy as np

from benchmarks.records import option
from engine.capture.downscale import downscaled_scene
from engine.formats.layout import SceneLayout
from engine.io.image_io import read_png
from engine.io.masks import dilate
from engine.metrics.image_metrics import psnr_from_mse
from engine.metrics.scores import hole_crop

RING = 8  # px past the true hole: the border a fill reads (coherence's reach is of this order at 320x240)


def mpsnr(out: np.ndarray, gt: np.ndarray, hole: np.ndarray) -> float:
    return psnr_from_mse(float(((out[hole] - gt[hole]) ** 2).mean()))


def scored(out: np.ndarray, gt: np.ndarray, hole: np.ndarray) -> tuple[float, np.ndarray, float]:
    """m-PSNR, the colour bias (the render's mean over the hole minus gt/'s) and m-PSNR with that bias removed."""
    bias = out[hole].mean(0) - gt[hole].mean(0)
    return mpsnr(out, gt, hole), bias, mpsnr(out - bias, gt, hole)


def main(args: list[str]) -> None:
    picture, args = option(args, "--picture")
    resolution, args = option(args, "--resolution")
    scene, sets = downscaled_scene(Path(args[0]), int(resolution or 1)), [a.split("=", 1) for a in args[1:]]
    tiles, totals, rings = [], {}, {}  # name -> per view, what scored() gives; name -> per view, the ring's bias
    for n in json.loads((SceneLayout(scene).split_json).read_text())["test"]:
        hole = read_png(SceneLayout(scene).holes / n, "mask") > 0
        if not hole.any():
            continue
        gt = read_png(SceneLayout(scene).gt / n) / 255.0
        flat = gt.copy()
        flat[hole] = gt[hole].mean(0)
        outs = {name: read_png(Path(d) / n) / 255.0 for name, d in sets}
        ring = dilate(hole, RING) & ~hole
        for k, o in outs.items():
            rings.setdefault(k, []).append(o[ring].mean(0) - gt[ring].mean(0))
        line = [f"{n} {int(hole.sum()):6d} px"]
        for k, o in (outs | {"flat oracle": flat, "blur oracle": cv2.GaussianBlur(gt, (0, 0), 4)}).items():
            totals.setdefault(k, []).append(scored(o, gt, hole))
            m, bias, unbiased = totals[k][-1]
            line.append(f"{k}={m:6.2f} (bias {np.round(bias * 255).astype(int)}, unbiased {unbiased:6.2f})"
                        if k in outs else f"{k}={m:6.2f}")
        print("  ".join(line))
        ys, xs = hole_crop(hole)
        crops = [gt] + list(outs.values())
        edge = cv2.dilate(hole.astype(np.uint8), np.ones((3, 3), np.uint8)) - hole.astype(np.uint8)
        tile = [np.where(edge[..., None] > 0, [1.0, 0, 1.0], c)[ys, xs] for c in crops]
        tiles.append(cv2.hconcat([cv2.resize(t.astype(np.float32), (192, 192), interpolation=cv2.INTER_NEAREST)
                                  for t in tile]))
    print("mean over views: " + ", ".join(f"{k} {np.mean([v[0] for v in vs]):.2f}" for k, vs in totals.items()))
    for k, _ in sets:  # the means the BENCHMARKS tables quote
        print(f"  {k}: bias {np.round(np.mean([v[1] for v in totals[k]], 0) * 255).astype(int)}, "
              f"m-PSNR without it {np.mean([v[2] for v in totals[k]]):.2f}, "
              f"ring's bias {np.round(np.mean(rings[k], 0) * 255).astype(int)}")
    if picture and tiles:
        cv2.imwrite(picture, (cv2.vconcat(tiles)[..., ::-1] * 255).round().astype(np.uint8))


if __name__ == "__main__":
    main(sys.argv[1:])
