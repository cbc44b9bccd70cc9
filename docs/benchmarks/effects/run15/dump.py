"""On the device, after `train`, `remove` and `holes` of a run: what the hole rule reads, cropped around the object,
so that variants of the rule can be tried on the CPU with the trained depths (issue 16, the tabletop's hole IoU).

Writes OUT.npz: per training view the removed scene's depth and the object's own (its Gaussians alone) inside the
object's box (its region dilated by MARGIN px), float16 relative to the object's median depth (the whole scene's, what
run_holes rendered then, is left out to stay within what a call brings back); per test view the removed render's
depth in the same kind of box; removal.json and holes.json as text. The first chain's dumps (MARGIN 48) held the
whole scene's depth instead of these two.
"""

import json
import sys
from pathlib import Path

import numpy as np
import torch

from engine.edit.removal import RemovalConfig, keep, select
from engine.io.image_io import exr_name, read_depth, read_png
from engine.render.render_views import render_depths
from engine.train.trained_run import load_run

MARGIN = 32


def box(region: np.ndarray) -> tuple[int, int, int, int]:
    ys, xs = np.nonzero(region)
    h, w = region.shape
    if not len(ys):
        return 0, 0, 0, 0
    return (max(0, ys.min() - MARGIN), min(h, ys.max() + MARGIN + 1), max(0, xs.min() - MARGIN),
            min(w, xs.max() + MARGIN + 1))


def main(run_dir: str, out: str) -> None:
    run = load_run(run_dir)
    scene, layout = run.scene, run.layout
    cams = [scene.cameras[i] for i in scene.train]
    depths_device = torch.device(sys.argv[3] if len(sys.argv) > 3 else "cuda")
    depths = render_depths(run.gaussians, cams, run.sh_degree, depths_device, "dump")
    regions = [read_png(layout.removed.masks / c.name, "mask", c.size) > 0 for c in scene.cameras]
    # the object's median rendered depth, as holes computed its `near` when the dumps were made
    seen = [d[regions[i] & np.isfinite(d)] for d, i in zip(depths, scene.train, strict=True)]
    near = float(np.median(np.concatenate(seen)))
    target = next(o.name for o in scene.objects if o.target)
    gone = keep(run.gaussians, ~select(run, RemovalConfig(run=run_dir, object=target))[0])
    gone_depths = render_depths(gone, cams, run.sh_degree, depths_device, "dump: the object alone")
    arrays = {"near": np.float64(near)}
    for k, i in enumerate(scene.train):
        y0, y1, x0, x1 = box(regions[i])
        arrays[f"trainbox_{scene.cameras[i].name}"] = np.array([y0, y1, x0, x1])
        arrays[f"gone_{scene.cameras[i].name}"] = (gone_depths[k][y0:y1, x0:x1] / near).astype(np.float16)
        removed_depth = read_depth(layout.removed.depth / exr_name(scene.cameras[i].name))
        arrays[f"trainremoved_{scene.cameras[i].name}"] = (removed_depth[y0:y1, x0:x1] / near).astype(np.float16)
    for i in scene.test:
        name = scene.cameras[i].name
        y0, y1, x0, x1 = box(regions[i])
        d = read_depth(layout.removed.depth / exr_name(name))
        arrays[f"removed_{name}"] = (d[y0:y1, x0:x1] / near).astype(np.float16)
        arrays[f"removedbox_{name}"] = np.array([y0, y1, x0, x1])
    for key, path in (("removal_json", layout.removed.report), ("holes_json", layout.holes.report)):
        arrays[key] = np.array(Path(path).read_text())
    np.savez_compressed(out, **arrays)
    print(out, Path(out).stat().st_size, json.loads(layout.holes.report.read_text())["mean_unseen_iou_vs_truth"])


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
