"""2D fills on exact data, the inpainters alone: each scored view's true hole (holes/) blanked in the truth (gt/)
and filled by each inpainter, m-PSNR against the truth in the hole and seconds per megapixel. What the 3D
pipeline adds (a removal's leftovers at the hole's border, depth, consistency) is not in it: a screen for which
2D fills are worth a cell in the held-out table, and the PatchMatch libraries from the registry beside ours.

    PYTHONPATH=. python benchmarks/fill_2d.py SCENE... [--every 4] [--json OUT]

The PatchMatch libraries are not the engine's requirements: `pip install patchmatch-cython pypatchmatch` where
this runs (a missing one is skipped and named in the output).
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from engine.formats.layout import SceneLayout
from engine.inpaint.registry import create
from engine.io.image_io import read_png
from engine.metrics.image_metrics import masked_psnr

OURS = ("telea", "navier-stokes", "fsr", "exemplar")


def inpainters() -> tuple[dict[str, Callable], dict[str, str]]:
    """name -> fill(rgb, hole) for ours and the registry's PatchMatch libraries, and those that could not load."""
    fills: dict[str, Callable] = {}
    missing = {}
    for name in OURS:
        try:
            inpainter = create(name)
        except Exception as exc:  # an inpainter whose requirement is absent here (fsr without contrib)
            missing[name] = str(exc)
            continue
        fills[name] = lambda im, m, inp=inpainter: inp.inpaint(im, m, "rgb")
    try:
        import patchmatch_cython

        fills["patchmatch-cython"] = lambda im, m: patchmatch_cython.inpaint_pyramid(im, m.astype(np.uint8))
    except ImportError as exc:
        missing["patchmatch-cython"] = str(exc)
    try:
        from patchmatch import patch_match

        patch_match.set_random_seed(0)
        fills["pypatchmatch"] = lambda im, m: patch_match.inpaint(im, m.astype(np.uint8) * 255, patch_size=3)
    except ImportError as exc:
        missing["pypatchmatch"] = str(exc)
    return fills, missing


def score(scene: Path, fills: dict[str, Callable], every: int) -> dict[str, list[tuple[float, float]]]:
    """(m-PSNR, seconds per megapixel) per view and inpainter, every `every`th view with a hole of 20 px or more."""
    out: dict[str, list[tuple[float, float]]] = {name: [] for name in fills}
    layout = SceneLayout(scene)
    for path in sorted(layout.holes.iterdir())[::every]:
        hole = read_png(path, kind="mask") > 0
        if hole.sum() < 20:
            continue
        truth = read_png(layout.gt / path.name)
        blank = truth.copy()
        blank[hole] = 0
        for name, fill in fills.items():
            start = time.perf_counter()
            filled = fill(blank, hole)
            seconds = time.perf_counter() - start
            out[name].append((masked_psnr(filled, truth, hole), seconds / (hole.size / 1e6)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="+", type=Path)
    parser.add_argument("--every", type=int, default=4, help="score every Nth view")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    fills, missing = inpainters()
    table = {}
    for scene in args.scenes:
        scored = score(scene, fills, args.every)
        table[scene.name] = {name: {"m_psnr": round(float(np.mean([p for p, _ in v])), 2),
                                    "s_per_mp": round(float(np.mean([s for _, s in v])), 2), "views": len(v)}
                             for name, v in scored.items() if v}
        print(scene.name, {k: (v["m_psnr"], v["s_per_mp"]) for k, v in table[scene.name].items()})
    names = list(fills)
    means = {n: round(float(np.mean([table[s][n]["m_psnr"] for s in table if n in table[s]])), 2) for n in names}
    print("mean m-PSNR", means, "missing", missing or "none")
    if args.json:
        args.json.write_text(json.dumps({"scenes": table, "mean_m_psnr": means, "missing": missing}, indent=1))


if __name__ == "__main__":
    main()
