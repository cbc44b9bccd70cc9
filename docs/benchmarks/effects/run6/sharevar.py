"""Removal with the visual hull's share relaxed, then the hole masks on each: removal PSNRs, hole IoU, crops."""

import json
import os
import sys

import cv2
import numpy as np

from engine.edit.holes import HoleConfig, run_holes
from engine.edit.removal import RemovalConfig, run_removal
from engine.io.image_io import read_png
from engine.train.trained_run import load_run

run_dir, obj_name, out = sys.argv[1:4]
DEV = sys.argv[4] if len(sys.argv) > 4 else "cuda"
shares = [float(s) for s in os.environ.get("SHARES", "1.0 0.9 0.8 0.7").split()]
res = {}
for share in shares:
    rm = f"/tmp/r/share_{share}"
    r = run_removal(RemovalConfig(run=run_dir, object=obj_name, out=rm, device=DEV, hull_share=share))
    h = run_holes(HoleConfig(run=run_dir, removed=rm, out=rm + "_holes", device=DEV))
    res[share] = {
        "removed": r["removed"],
        "selected_by": r["selected_by"],
        "psnr_outside_hole": r["psnr_outside_hole"],
        "psnr_revealed": r["psnr_revealed"],
        "effects": r["effects"]["search"],
        "recall": r["effects"]["recall"],
        "precision": r["effects"]["precision"],
        "hole_iou": h["mean_iou_vs_truth"],
    }
    print(
        "SHARE",
        share,
        {k: v for k, v in res[share].items() if k != "effects"},
        r["effects"]["search"]["verdict"],
        flush=True,
    )
json.dump(res, open(f"{out}_sharevar.json", "w"), indent=1)
run = load_run(run_dir)
scene = run.scene
obj = scene.object_by(obj_name)
rows = []
for i in scene.test[:5]:
    cam = scene.cameras[i]
    m = scene.masks[i] == obj.id
    ys, xs = np.nonzero(m)
    y0, y1, x0, x1 = max(ys.min() - 10, 0), ys.max() + 10, max(xs.min() - 10, 0), xs.max() + 10
    panels = [scene.images[i], scene.gt_images[i]] + [read_png(f"/tmp/r/share_{s}/images/{cam.name}") for s in shares]
    rows.append(np.concatenate([p[y0:y1, x0:x1] for p in panels], 1))
w = max(r.shape[1] for r in rows)
rows = [np.pad(r, ((0, 4), (0, w - r.shape[1]), (0, 0))) for r in rows]
cv2.imwrite(f"{out}_share_crops.png", cv2.cvtColor(np.concatenate(rows, 0), cv2.COLOR_RGB2BGR))
