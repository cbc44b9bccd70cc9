"""Session 27: the test fixture's tiny livingroom run (tests/conftest.py tiny_run: 800 steps, densifying 50-150)
trained with several seeds on one scene, each scored by both criteria of tests/test_segments.py: lifting the
scene's masks with ids shuffled per view (at segment's default floor of 20 Gaussians an object), and --auto.

    PYTHONPATH=.:tests .venv/bin/python docs/benchmarks/segments/peel/tiny_seeds.py SCENE WORK 0,1,2,3,4

Runs in WORK are reused, so the same runs are scored by whichever code tree this runs from (records.txt:
before and after fa6729a)."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import numpy as np
from test_segments import shuffled_masks

from engine.metrics.segment_scores import iou, proposal_scores
from engine.train.config import TrainConfig
from engine.train.run import train
from engine.train.segments import SegmentConfig, run_segment
from engine.train.trained_run import load_run, load_run_scene


def copy_run(run: Path, to: Path) -> Path:
    shutil.rmtree(to, ignore_errors=True)
    shutil.copytree(run, to, ignore=shutil.ignore_patterns("checkpoints", "segments"))
    return to


def from_masks(run: Path, work: Path) -> tuple:
    """(objects, joined, segments, the best object's target IoU on the test views)."""
    scene = load_run_scene(run)
    target = shuffled_masks(run, work / "masks")
    report = run_segment(load_run(run), SegmentConfig(run=str(run), from_masks=str(work / "masks"), device="cpu"))
    found = load_run_scene(run)
    best = max(np.mean([iou(found.masks[i] == o.id, scene.masks[i] == target) for i in scene.test])
               for o in found.objects)
    return report["objects"], report["joined"], report["segments"], round(float(best), 3)


def auto(run: Path) -> tuple:
    """(planes, objects, the target's best proposal IoU on the test views)."""
    scene = load_run_scene(run)
    report = run_segment(load_run(run), SegmentConfig(run=str(run), auto=True, device="cpu"))
    found = load_run_scene(run)
    scores = proposal_scores([found.masks[i] for i in scene.test], [scene.masks[i] for i in scene.test],
                             [o.id for o in scene.objects])
    return report["planes"], report["objects"], scores["objects"][scene.target.id]["iou"]


def main(scene: str, root: Path, seeds: list[int]) -> None:
    for seed in seeds:
        run = root / f"run{seed}"
        if not (run / "metrics.json").exists():
            train(TrainConfig(scene=scene, out=str(run), preset="tiny", device="cpu", steps=800, refine_start=50,
                              refine_stop=150, seed=seed))
        metrics = json.loads((run / "metrics.json").read_text())
        out = {"seed": seed, "psnr": round(metrics["psnr"], 2), "miou": round(metrics["identity_miou"], 3),
               "gaussians": metrics["gaussians"],
               "masks": from_masks(copy_run(run, root / f"masks{seed}" / "run"), root / f"masks{seed}"),
               "auto": auto(copy_run(run, root / f"auto{seed}"))}
        print("RESULT", json.dumps(out), flush=True)


if __name__ == "__main__":
    main(sys.argv[1], Path(sys.argv[2]), [int(s) for s in sys.argv[3].split(",")])
