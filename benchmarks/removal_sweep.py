"""Benchmark removal and hole masks on a generated scene: which threshold, hull or not, which tolerance.

    python benchmarks/removal_sweep.py --scene DIR [--run RUN | --budget 100000] --results DIR
    python benchmarks/removal_sweep.py --report [--results DIR]        # DIR/*.json -> DIR/tables.md

For each identity threshold, with and without the visual-hull clean-up: Gaussians removed, and PSNR of the
removed scene against gt/ outside the true hole on test views (what removal leaves behind: remnants of the
object and floaters lower it). Then hole masks at several depth tolerances: mean IoU against the scene's
exact holes/, hole size relative to the object's region, seconds, with and without stopping rays at the
support plane (engine.edit.support_plane). Engine Python; GPU for real scenes.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from benchmarks.records import RESULTS as ALL_RESULTS  # noqa: E402
from benchmarks.records import load_records, provenance, report_or_measure, save_record, write_tables  # noqa: E402

RESULTS = ALL_RESULTS / "removal"


def measure(scene: Path, run: Path, thresholds: list[float], tolerances: list[float], margins: list[float],
            work: Path) -> dict:
    from engine.capture.scene import load_scene
    from engine.edit.holes import HoleConfig, run_holes
    from engine.edit.removal import RemovalConfig, run_removal

    target = load_scene(scene).target
    removals = []
    for threshold in thresholds:
        for hull in (False, True):
            start = time.perf_counter()
            report = run_removal(RemovalConfig(run=str(run), object=str(target.id), threshold=threshold, hull=hull,
                                               out=str(work / f"removed_{threshold}_{hull}")))
            removals.append({"threshold": threshold, "hull": hull, "removed": report["removed"],
                             "psnr_outside_hole": round(report["psnr_outside_hole"], 2),
                             "psnr_revealed": report["psnr_revealed"] and round(report["psnr_revealed"], 2),
                             "seconds": round(time.perf_counter() - start, 1)})
    default = RemovalConfig()
    removed = work / f"removed_{default.threshold}_{default.hull}"
    holes = []
    base = HoleConfig()
    variants = [(tol, base.support_plane, base.occluder_margin) for tol in tolerances]
    variants += [(base.rel_tol, False, base.occluder_margin)]
    variants += [(base.rel_tol, base.support_plane, margin) for margin in margins if margin != base.occluder_margin]
    for tol, plane, margin in variants:
        start = time.perf_counter()
        out = work / f"holes_{tol}_{plane}_{margin}"
        report = run_holes(HoleConfig(run=str(run), removed=str(removed), out=str(out), rel_tol=tol,
                                      support_plane=plane, occluder_margin=margin))
        holes.append({"rel_tol": tol, "support_plane": plane, "occluder_margin": margin,
                      "mean_iou": round(report["mean_unseen_iou_vs_truth"], 3),
                      "hole_to_region": round(report["hole_to_region"], 3),
                      "seconds": round(time.perf_counter() - start, 1)})
    return {"removals": removals, "holes": holes}


def run_bench(args: argparse.Namespace) -> None:
    from engine.formats.protocol import refuse_held_out
    from engine.train.config import TrainConfig
    from engine.train.run import train

    scene = Path(args.scene)
    refuse_held_out(scene, "removal_sweep.py")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = args.work or tmp
        run = Path(args.run) if args.run else Path(tmp) / "run"
        metrics = None
        if not args.run:
            metrics = train(TrainConfig(scene=str(scene), out=str(run), max_gaussians=args.budget))
        record = {"scene": scene.name, "budget": args.budget, "train_psnr": metrics and round(metrics["psnr"], 2),
                  **measure(scene, run, args.thresholds, args.tolerances, args.margins, Path(tmp)), **provenance()}
    save_record(Path(args.results), scene.name, record)


def report(results: Path) -> None:
    lines = []
    for r in load_records(results):
        lines += [f"**{r['scene']}** ({r['device']}, trained with budget {r['budget']}, test PSNR {r['train_psnr']})",
                  "", "| threshold | hull | Gaussians removed | PSNR outside true hole | PSNR revealed | seconds |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| {m['threshold']} | {'yes' if m['hull'] else 'no'} | {m['removed']:,} | "
                  f"{m['psnr_outside_hole']} | {m.get('psnr_revealed')} | {m['seconds']} |" for m in r["removals"]]
        lines += ["", "| depth tolerance | support plane | occluder margin (x diagonal) | hole IoU vs truth "
                  "| hole / object pixels | seconds |", "|---|---|---|---|---|---|"]
        lines += [f"| {h['rel_tol']} | {_plane(h)} | {h.get('occluder_margin', 0)} | {h['mean_iou']} | "
                  f"{h['hole_to_region']} | {h['seconds']} |" for h in r["holes"]]
        lines += ["", f"Command: `{r['command']}`", ""]
    write_tables(results, "Removal thresholds and hole-mask settings", lines)


def _plane(hole: dict) -> str:
    if "support_plane" not in hole:
        return "no (before the plane rule)"
    return "yes" if hole["support_plane"] else "no"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene")
    parser.add_argument("--run", help="an existing training run of --scene (default: train one)")
    parser.add_argument("--budget", type=int, default=100_000)
    parser.add_argument("--thresholds", type=float, nargs="*", default=[0.1, 0.3, 0.5, 0.7, 0.9])
    parser.add_argument("--tolerances", type=float, nargs="*", default=[0.005, 0.01, 0.02])
    parser.add_argument("--margins", type=float, nargs="*", default=[0, 0.005, 0.02],
                        help="occluder margins to try, as fractions of the image diagonal")
    parser.add_argument("--work", help="keep the runs, removals and hole masks here (default: a temporary folder)")
    return report_or_measure(parser, RESULTS, report, run_bench)


if __name__ == "__main__":
    sys.exit(main())
