"""Hole IoU of a run's holes stage at several occluder margins (px)."""

import sys
import time

from engine.edit.holes import HoleConfig, run_holes

run, out = sys.argv[1], sys.argv[2]
for m in [int(a) for a in sys.argv[3:]]:
    t = time.time()
    r = run_holes(HoleConfig(run=run, out=f"{out}/holes_{m}", occluder_margin=m, device="cuda"))
    print(
        "RESULT",
        run,
        m,
        round(r["mean_iou_vs_truth"], 3),
        [round(v["iou_vs_truth"], 2) for v in r["views"] if "iou_vs_truth" in v],
        round(r["hole_to_region"], 3),
        f"{time.time() - t:.0f}s",
        flush=True,
    )
