"""The highest "hole IoU as inpainted" any hole masks can reach at a given growth: the generator's exact holes/
themselves, grown by D px as `inpaint` grows the masks it fills, scored as `inpaint` scores them
(engine.inpaint.run.inpainted_hole_iou: per view with holes/, the IoU against the exact hole; mean and worst).

Why: the inpaint stage's growth (GROW_SHARE of the width, 3 px at 320) is part of what it is scored on, and a
hole a few px across loses most of its IoU to it however exact the masks are; the table says which target a
growth leaves reachable before any mask is judged. No training, no GPU: the scenes' holes/ alone.

    PYTHONPATH=. python benchmarks/hole_iou_ceiling.py OUT.json SCENE... [--grow 0 1 2 3]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from engine.capture.scene import load_scene
from engine.edit.holes import iou
from engine.inpaint.run import dilation_px
from engine.io.masks import dilate
from engine.metrics.image_metrics import mean_and_worst


def grown_scores(truths: list[np.ndarray], grow: int) -> dict:
    """IoU of each exact hole grown by `grow` px against itself, over views (mean_and_worst)."""
    return mean_and_worst([iou(dilate(truth, grow), truth) for truth in truths])


def scene_row(scene_dir: Path, grows: list[int]) -> dict:
    """One scene's ceiling per growth, beside its default growth in px and its holes' median size."""
    scene = load_scene(scene_dir)
    truths = [mask for _, mask in sorted(scene.holes.items())]
    if not truths:
        raise SystemExit(f"{scene_dir}: no holes/ (make the scene with --gt all)")
    default = dilation_px(-1, scene.cameras)
    return {"default_grow_px": default, "views": len(truths),
            "median_hole_px": float(np.median([t.sum() for t in truths])),
            "by_grow_px": {str(g): grown_scores(truths, g) for g in sorted({*grows, default})}}


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="the record (JSON)")
    parser.add_argument("scenes", nargs="+", help="generated scenes with holes/")
    parser.add_argument("--grow", nargs="+", type=int, default=[0, 1, 2, 3], help="growths in px")
    args = parser.parse_args(argv)
    rows = {Path(s).name: scene_row(Path(s), args.grow) for s in args.scenes}
    for name, row in rows.items():
        cells = ", ".join(f"{g} px {r['mean']:.3f}" for g, r in row["by_grow_px"].items())
        print(f"{name}: median hole {row['median_hole_px']:.0f} px; {cells}")
    means = {g: float(np.mean([row["by_grow_px"][g]["mean"] for row in rows.values()]))
             for g in next(iter(rows.values()))["by_grow_px"]}
    print("mean over scenes: " + ", ".join(f"{g} px {m:.3f}" for g, m in means.items()))
    Path(args.out).write_text(json.dumps({"what": __doc__.split("\n\n")[0], "scenes": rows,
                                          "mean_over_scenes": means}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
