"""Benchmark objects found without ground-truth masks (engine.segment.run) on generated scenes, whose
exact instance masks are hidden from `segment` and used only to score it.

    python benchmarks/segments.py --run RUN [--run RUN ...] --results DIR [--from-run]
    python benchmarks/segments.py --report [--results DIR]        # DIR/*.json -> DIR/tables.md

Per run: `segment --auto` (geometry and salient votes): per ground-truth object the best proposal's mask IoU
on the test views, whether object_1 (the subject) is the target, proposals that merge two objects, seconds.
`--from-run` scores the objects the run's own `segment --auto` wrote instead of finding them again (gpu.sh's
`subject` job, which removes object_1 after: one search, not two, on a machine whose minutes are counted).
Then `--from-masks` with the training views' exact masks perturbed as a 2D tool gives them (ids shuffled per
view, 10% of the segments split or merged): the share of segments associated to the right object, and the
target's IoU on the test views. Engine Python; GPU for full-size runs.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from benchmarks.records import RESULTS as ALL_RESULTS  # noqa: E402
from benchmarks.records import load_records, provenance, report_or_measure, save_record, write_tables  # noqa: E402

RESULTS = ALL_RESULTS / "segments"


def _masks(segments: Path, names: list[str]):
    """The instance masks `segment` wrote into the segments folder `segments`, for these image names."""
    from engine.formats.layout import SegmentsLayout
    from engine.io.image_io import read_png

    return [read_png(SegmentsLayout(segments).masks / Path(n).with_suffix(".png"), kind="mask") for n in names]


def measure(run_dir: Path, work: Path, pictures: Path, solid: float, seed: int = 0, from_run: bool = False) -> dict:
    import numpy as np

    from engine.capture.scene import load_scene
    from engine.formats.layout import RunLayout, SegmentsLayout
    from engine.io.image_io import write_png
    from engine.metrics.segment_scores import association_accuracy, perturb_masks, proposal_scores
    from engine.segment.run import SegmentConfig, run_segment
    from engine.train.trained_run import load_run

    run = load_run(run_dir)
    scene = load_scene(run.config.scene, run.config.resolution)  # the truth: load_run reads the run's segments in
    # place of the scene's objects and masks where `segment` wrote them
    test = [scene.cameras[i].name for i in scene.test]
    truth_test = [scene.masks[i] for i in scene.test]
    ids = [o.id for o in scene.objects]
    if from_run:
        auto_dir, seconds = RunLayout(run_dir).segments.root, None
        auto = json.loads(SegmentsLayout(auto_dir).report.read_text())
        solid = auto["config"]["solid"]
    else:
        auto_dir, start = work / "auto", time.perf_counter()
        auto = run_segment(run, SegmentConfig(run=str(run_dir), auto=True, solid=solid, out=str(auto_dir)))
        seconds = round(time.perf_counter() - start, 1)
    scores = proposal_scores(_masks(auto_dir, test), truth_test, ids)
    pictures.mkdir(parents=True, exist_ok=True)
    shutil.copy(SegmentsLayout(auto_dir).sheet, pictures / f"{scene.root.name}-auto-solid{solid:g}.png")
    names = {o.id: o.name for o in scene.objects}
    record = {"scene": scene.root.name, "gaussians": len(run.gaussians["means"]), "views": len(scene.cameras),
              "size": [scene.cameras[0].width, scene.cameras[0].height], "target": scene.target.name,
              "auto": {"seconds": seconds, "proposals": auto["objects"], "planes": auto.get("plane_heights"),
                       "solid": solid, "weak_evidence": auto.get("weak_evidence"),
                       "merges": scores["merges"], "target_iou": scores["objects"][scene.target.id]["iou"],
                       "subject": auto.get("subject"),
                       "subject_is_target": scores["objects"][scene.target.id]["found"] == 1,
                       "objects": {names[g]: s["iou"] for g, s in scores["objects"].items()}}}
    given, owners = perturb_masks([scene.masks[i] for i in scene.train], np.random.default_rng(seed))
    for i, mask in zip(scene.train, given, strict=True):
        write_png(work / "given" / Path(scene.cameras[i].name).with_suffix(".png"), mask)
    start = time.perf_counter()
    lifted = run_segment(run, SegmentConfig(run=str(run_dir), from_masks=str(work / "given"), out=str(work / "lift")))
    seconds = time.perf_counter() - start
    train_names = [scene.cameras[i].name for i in scene.train]
    found = _masks(work / "lift", train_names)
    lifted_scores = proposal_scores(_masks(work / "lift", test), truth_test, ids)
    record["masks"] = {"seconds": round(seconds, 1), "segments": lifted["segments"], "objects": lifted["objects"],
                       "association": round(association_accuracy(given, owners, found), 4),
                       "target_iou": lifted_scores["objects"][scene.target.id]["iou"]}
    return record


def run_bench(args: argparse.Namespace) -> None:
    from engine.geometry.scene_geometry import ProposalConfig

    args.solid = ProposalConfig.solid if args.solid is None else args.solid
    for run in args.run:
        with tempfile.TemporaryDirectory() as tmp:
            record = {**measure(Path(run), Path(tmp), Path(args.results) / "pictures", args.solid,
                                from_run=args.from_run), **provenance()}
        save_record(Path(args.results), f"{record['scene']}-solid{record['auto']['solid']:g}", record)


def report(results: Path) -> None:
    lines = ["| scene | views, size | Gaussians | auto: proposals | target IoU (test views) | merges | other "
             "objects' best IoU | seconds | user masks: association | target IoU | seconds | device |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in load_records(results):
        a, m = r["auto"], r["masks"]
        others = ", ".join(f"{k} {v:.2f}" for k, v in a["objects"].items() if k != r["target"])
        lines.append(f"| {r['scene']} | {r['views']}, {r['size'][0]}x{r['size'][1]} | {r['gaussians']:,} | "
                     f"{a['proposals']} | {a['target_iou']:.2f} | {a['merges']} | {others} | {a['seconds']} | "
                     f"{m['association']:.3f} | {m['target_iou']:.2f} | {m['seconds']} | {r['device']} |")
    commands = sorted({r["command"] for r in load_records(results)})
    lines += ["", "Commands: " + "; ".join(f"`{c}`" for c in commands)]
    write_tables(results, "Objects without ground-truth masks", lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", nargs="*", default=[], help="training runs of generated scenes")
    parser.add_argument("--solid", type=float, help="segment --solid (default: segment's)")
    parser.add_argument("--from-run", action="store_true",
                        help="score the objects the run's own `segment --auto` wrote instead of searching again")
    return report_or_measure(parser, RESULTS, report, run_bench)


if __name__ == "__main__":
    sys.exit(main())
