"""The benchmark matrix: scene x method x inpainter x seed, through the engine, resumable, with tables.

    blender -b -P scripts/benchmark.py -- --scenes DIR... --methods init ft3 --inpainters fsr --seeds 0 1 --out DIR
    python scripts/benchmark.py --scenes DIR... ...          # the same with any Python (no torch needed here)

Per scene and seed the shared stages run once (train, remove the scene's target, holes, inpaint per
inpainter, and the direct 2D step for `direct`), then each method completes the scene in a cell of its own:
OUT/work/<scene>/seed<k>/run/complete/<Name>/ with scores.json. Every stage skips work already on disk,
so a run that was interrupted continues where it stopped, and a finished cell is never run again. A cell
that fails is recorded with its one-line reason and the others go on. Runs of different seeds or scenes
may share one --out at the same time (their work folders differ); `--report-only` then writes the
tables from every finished cell without running anything.

Cells run as Ray tasks, two trainings sharing each GPU (benchmarks/matrix_ray.py, --trainings-per-gpu): on this
machine's GPUs, or on a Ray cluster with --ray-address; `--scheduler serial` (and any Python without Ray) runs
them one after the other here.

Writes OUT/results.json and results.csv (one row per cell), and OUT/tables.md: per scene and averaged over
scenes, the paper's columns (mean over seeds; best in bold), with the removed-but-unfilled scene as the
first row; OUT/stability.md and OUT/speed_accuracy.svg and .png (benchmarks/matrix_report.py); OUT/pictures/
<scene>.png, the first seed's test views side by side (GT, then each method). Methods: the
benchmark cells the completion-method plug-ins declare (engine/complete/methods; `--list-methods`): init,
init-colmap (Init on poses COLMAP re-estimates from the inpainted images, the paper's ablation), reference
(Ref: one view's fill carried to every view), direct, ft3, ftall. Run time of a method is end to end: every
stage it needs (train + remove + holes + inpaint + complete; Direct, which paints the input images, all but the
holes), as a user running that method alone waits; `Share (s)` splits each shared stage among the cells that
used it. FID and KID stay in the per-scene tables (a set metric is not averaged across scenes) and are n/a over
fewer than 50 images a side (engine.metrics.scores).
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from pathlib import Path

from addon.engine_call import EngineError, run_engine
from benchmarks.matrix_ray import TRAININGS_PER_GPU
from benchmarks.matrix_report import write_reports
from benchmarks.matrix_stages import Stages, run_cell
from engine.complete.registry import benchmark_cells, get
from engine.formats.layout import RunLayout, SceneLayout
from scripts.blender_entry import script_args

COLUMNS = [("psnr", "PSNR", max), ("m_psnr", "m-PSNR", max), ("ssim", "SSIM", max), ("m_ssim", "m-SSIM", max),
           ("lpips", "LPIPS", min), ("m_lpips", "m-LPIPS", min),
           ("st_lpips", "ST-LPIPS", min), ("m_st_lpips", "m-ST-LPIPS", min),
           ("psnr_kept", "Kept (dB)", max), ("fid", "FID", min), ("m_fid", "m-FID", min),
           ("kid", "KID", min), ("m_kid", "m-KID", min), ("seconds", "Run time (s)", min),
           ("share_seconds", "Share (s)", min),
           ("gaussians", "Gaussians", None)]


def _fmt(value, key: str) -> str:
    if value is None:
        return "n/a"
    if key == "gaussians":
        return f"{int(value):,}"
    four = ("ssim", "m_ssim", "lpips", "m_lpips", "st_lpips", "m_st_lpips", "kid", "m_kid")
    return f"{value:.4f}" if key in four else f"{value:.2f}"


def _ranked(row: str) -> bool:
    """Methods are ranked; the unfilled floor and the oracles' ceiling are references beside them."""
    return row != "Removed (unfilled)" and not row.startswith("Oracle")


def _table(rows: dict[str, dict[str, float | None]]) -> list[str]:
    lines = ["| Method | " + " | ".join(label for _, label, _ in COLUMNS) + " |",
             "|---" * (len(COLUMNS) + 1) + "|"]
    best = {}
    for key, _, pick in COLUMNS:
        values = [r[key] for name, r in rows.items() if r.get(key) is not None and _ranked(name)]
        best[key] = pick(_rank_value(v, key) for v in values) if pick and values else None
    for name, r in rows.items():
        cells = [(f"**{_fmt(r.get(key), key)}**" if best[key] is not None and r.get(key) is not None
                  and _rank_value(r[key], key) == best[key] and _ranked(name) else _fmt(r.get(key), key))
                 for key, _, _ in COLUMNS]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines


ORACLES = (("flat", "Oracle: truth's mean colour"), ("blur", "Oracle: truth blurred 4 px"))  # never ranked
DISTRIBUTION = ("fid", "m_fid", "kid", "m_kid")  # set metrics: never averaged across scenes (METRICS.md)


def _rank_value(value: float, key: str) -> float:
    """What a column is ranked by: KID estimates a squared distance, so a negative one is zero (noise), never
    better than zero."""
    return max(value, 0.0) if key in ("kid", "m_kid") else value


def _mean(values: list) -> float | None:
    kept = [v for v in values if v is not None]
    return sum(kept) / len(kept) if kept else None


def add_shares(cells: list[dict]) -> list[dict]:
    """Each finished cell with `share_seconds`: its completion plus, for each shared stage it needs (base run,
    removal, holes, inpainting), that stage's seconds split evenly among the finished cells of its scene and seed
    that need it. `seconds` stays the end-to-end time a user running that one method would wait."""
    users: dict[tuple, int] = {}
    for c in cells:
        for stage in c.get("stages") or {}:
            users[(c["scene"], c["seed"], stage)] = users.get((c["scene"], c["seed"], stage), 0) + 1
    return [c | {"share_seconds": round(c["complete_seconds"] + sum(
        s / users[(c["scene"], c["seed"], k)] for k, s in c["stages"].items()), 1)} if c.get("stages") else c
        for c in cells]


def summarise(cells: list[dict]) -> dict[str, dict[str, dict]]:
    """Per scene, and averaged over scenes ('all'; 'all held-out', 'all tuning' and 'all other' when the scenes'
    roles differ, engine.formats.protocol), per method: each column's mean over seeds (and scenes)."""
    done = [c for c in cells if c["status"] == "done"]  # with their shares (add_shares) when write_results calls
    scenes = sorted({c["scene"] for c in done})
    roles = [r for r in ("held-out", "tuning", None) if any(c.get("role") == r for c in done)]
    groups = {scene: [c for c in done if c["scene"] == scene] for scene in scenes}
    for role in roles:  # held-out and tuning scenes are never averaged together
        groups["all" if len(roles) == 1 else f"all {role or 'other'}"] = [c for c in done if c.get("role") == role]
    out: dict[str, dict[str, dict]] = {}
    for scene, chosen in groups.items():
        kept = [k for k, _, _ in COLUMNS if not (scene.startswith("all") and k in DISTRIBUTION)]
        rows = {"Removed (unfilled)": {k: _mean([c["removed_scores"].get(k) for c in chosen])
                                       for k in kept if k not in ("seconds", "gaussians")}}
        for oracle, label in ORACLES:
            scores = [(c.get("oracle_scores") or {}).get(oracle) or {} for c in chosen]
            if any(scores):
                rows[label] = {k: _mean([o.get(k) for o in scores]) for k in ("psnr", "ssim", "m_psnr", "m_ssim")}
        for name in sorted({c["method"] for c in chosen}):
            mine = [c for c in chosen if c["method"] == name]
            rows[name] = {k: _mean([c.get(k) for c in mine]) for k in kept}
        out[scene] = rows
    return out


def cell_commit(cell: dict) -> str | None:
    """The code a finished cell's completion ran (its base run's, for records made before cells kept their own)."""
    return cell.get("commit") or ((cell.get("settings") or {}).get("versions") or {}).get("commit")


class MixedCommits(Exception):
    """Finished cells of several code versions, to be tabulated only when asked (--mixed-commits)."""


def mark_commits(cells: list[dict], mixed: bool) -> list[dict]:
    """The cells, refused with one line when the finished ones come from more than one code version, unless
    `mixed`: then each method's name carries its commit, so no table row silently averages two codes."""
    commits = sorted({str(cell_commit(c)) for c in cells if c["status"] == "done"})
    if len(commits) <= 1:
        return cells
    if not mixed:
        raise MixedCommits(f"the finished cells come from {len(commits)} commits ({', '.join(commits)}): run them "
                         "again at one commit, or pass --mixed-commits to tabulate them marked")
    return [c | {"method": f"{c['method']} @{cell_commit(c)}"} if c["status"] == "done" else c for c in cells]


def _hole_line(cells: list[dict], scene: str) -> list[str]:
    """The scene's hole masks and removal over every view with a truth (means over its seeds): the masks' IoU as
    `holes` wrote them, as the inpainting filled them (mean and worst view), their unseen part; the removal's PSNR
    outside the true hole (mean and worst view)."""
    runs = [c for c in cells if c["scene"] == scene and c.get("hole_iou") is not None]
    if not runs:
        return []
    keys = ("hole_iou", "hole_iou_inpainted", "hole_iou_inpainted_worst", "unseen_iou", "removal_psnr_outside",
            "removal_psnr_outside_worst")
    m = {k: _mean([c.get(k) for c in runs]) for k in keys}
    said = [f"Hole masks, mean IoU against the true holes: {m['hole_iou']:.3f} as written"]
    if m["hole_iou_inpainted"] is not None:
        said.append(f"{m['hole_iou_inpainted']:.3f} as inpainted (worst view {m['hole_iou_inpainted_worst']:.3f})")
    if m["unseen_iou"] is not None:
        said.append(f"{m['unseen_iou']:.3f} for their unseen part alone")
    line = ", ".join(said)
    if m["removal_psnr_outside"] is not None:
        line += (f". Removal, PSNR outside the true hole: {m['removal_psnr_outside']:.2f} dB (worst view "
                 f"{m['removal_psnr_outside_worst']:.2f})")
    return [line, ""]


def write_results(cells: list[dict], out: Path, mixed: bool = False) -> None:
    """results.json and results.csv (every cell as recorded), then the tables, chart and failure report, which
    take the cells of one commit only unless `mixed` (`MixedCommits` otherwise, after the records are written)."""
    cells = add_shares(cells)
    (out / "results.json").write_text(json.dumps(cells, indent=1))
    keys = ["scene", "seed", "inpainter", "method", "status", "reason", "commit"] + [k for k, _, _ in COLUMNS]
    with open(out / "results.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(cells)
    cells = mark_commits(cells, mixed)
    lines = ["# Benchmark results", ""]
    roles = {c["scene"]: c.get("role") for c in cells}
    for scene, rows in summarise(cells).items():
        title = (f"Averaged over {scene[4:]} scenes" if scene.startswith("all ") else "Averaged over scenes"
                 if scene == "all" else f"Scene: {scene}" + (f" ({roles[scene]})" if roles.get(scene) else ""))
        lines += [f"## {title}", "", *_hole_line(cells, scene), *_table(rows), ""]
    failed = [c for c in cells if c["status"] == "failed"]
    if failed:
        lines += ["## Failed cells", ""] + [f"- {c['scene']} seed {c['seed']} {c['method']}: {c['reason']}"
                                            for c in failed] + [""]
    missing = [c for c in cells if c["status"] == "not run"]
    if missing:
        lines += ["## Cells not run", ""] + [f"- {c['scene']} seed {c['seed']} {c['method']}" for c in missing] + [""]
    reasons: dict[str, set[str]] = {}
    for c in cells:
        for key, reason in (c.get("unavailable") or {}).items():
            reasons.setdefault(reason, set()).add(key)
    reasons.setdefault("a set metric: not averaged across scenes (in the scene tables only)", set()).update(
        DISTRIBUTION)
    if reasons:
        lines += ["n/a columns:", ""] + [f"- {', '.join(sorted(keys))}: {reason}" for reason, keys in
                                         sorted(reasons.items())] + [""]
    (out / "tables.md").write_text("\n".join(lines))
    write_reports(cells, out)


def pictures(cells: list[dict], out: Path, seed: int, views: int = 4) -> None:
    """Per scene, the first seed's test views side by side: the object's region, its effects and the hole
    masks (white) where the run has them, ground truth, then each finished method."""
    for scene in sorted({c["scene"] for c in cells}):
        done = [c for c in cells if c["scene"] == scene and c["seed"] == seed and c["status"] == "done"]
        if not done:
            continue
        scene_dir = Path(done[0]["scene_dir"])
        folders = [(c["method"], Path(c["renders"])) for c in done]
        names = sorted(p.name for p in folders[0][1].glob("*.png"))[:views]
        run = RunLayout(folders[0][1].parents[2])  # RUN/complete/<Name>/renders
        masks = [(k, f) for k, f in (("region", run.removed.masks), ("effects", run.removed.effects.root),
                                     ("hole", run.holes.root)) if f.is_dir()]
        try:
            run_engine(["compare", "--out", str(out / "pictures" / f"{scene}.png"), "--views", *names,
                        "--columns", *(f"{k}={f}" for k, f in masks), f"GT={SceneLayout(scene_dir).gt}",
                        *(f"{m}={f}" for m, f in folders)])
        except EngineError as exc:
            print(f"no picture for {scene}: {exc}", flush=True)


def run_matrix(matrix: list[tuple[Path, int, str, str]], args: argparse.Namespace, work: Path):
    """(index in `matrix`, cell) as each cell finishes: one after the other here, or as Ray tasks on every
    GPU (benchmarks/matrix_ray.py; the default where Ray is installed)."""
    if args.scheduler == "ray" and not args.report_only:
        try:
            import ray  # noqa: F401
        except ImportError:
            print("Ray is not installed here (pip install ray): the cells run one after the other", flush=True)
        else:
            from benchmarks.matrix_ray import run_cells

            sources = {m: get(benchmark_cells()[m].method).source for m in args.methods}
            yield from run_cells(matrix, sources, work, args)
            return
    for index, (scene, seed, inpainter, method) in enumerate(matrix):
        yield index, run_cell(Stages(scene, seed, work, args), method, inpainter, args)


def build_parser() -> argparse.ArgumentParser:
    """The matrix's flags; a setting left out is the engine's own default (its CLI's and the add-on's)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", nargs="+")
    cells = list(benchmark_cells())
    parser.add_argument("--methods", nargs="+", default=["init", "reference", "ft3", "ftall", "direct"], choices=cells,
                        help="benchmark cells, from the completion methods' plug-ins: " + ", ".join(cells))
    parser.add_argument("--list-methods", action="store_true", help="print the benchmark's cells and exit")
    parser.add_argument("--inpainters", nargs="+", default=["telea", "exemplar"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1])
    parser.add_argument("--out")
    parser.add_argument("--preset", default="default")
    parser.add_argument("--steps", type=int, default=0, help="training steps of the base runs (0: the preset's)")
    parser.add_argument("--complete-steps", type=int, default=0,
                        help="steps of the completions that train a new scene from scratch (the -scratch cells; 0: "
                             "the base run's)")
    parser.add_argument("--short-steps", type=int, default=0,
                        help="steps of those that continue from the base run's scene (FT; Init, Ref and Direct, "
                             "warm by default; 0: a tenth of the base run's)")
    parser.add_argument("--max-gaussians", type=int, default=None,
                        help="Gaussian budget of the base runs (default: the preset's, as `engine train` has it)")
    parser.add_argument("--dilate", type=int, default=None,
                        help="px added to the masks before inpainting (default: `engine inpaint`'s)")
    parser.add_argument("--perceptual", default=None,
                        help="FT's perceptual term (lpips | st-lpips | l1; default: the method's, as `engine "
                             "complete` has it)")
    parser.add_argument("--device", default="auto")
    parser.add_argument("--scheduler", choices=("ray", "serial"), default="ray",
                        help="ray: cells as Ray tasks sharing GPUs (--trainings-per-gpu), on this machine's GPUs "
                             "(or the cluster at --ray-address); serial: one after the other in this process (also "
                             "where Ray is absent)")
    parser.add_argument("--ray-address", default="", help="a running Ray cluster (default: start one here)")
    parser.add_argument("--trainings-per-gpu", type=int, default=TRAININGS_PER_GPU,
                        help="Ray: training stages (base runs, cells) that may share one GPU at once (default: "
                             f"{TRAININGS_PER_GPU}, the fastest measured)")
    parser.add_argument("--report-only", action="store_true",
                        help="run nothing: write the tables, chart and pictures from the cells already finished "
                             "(for example after several runs of single seeds into one --out)")
    parser.add_argument("--mixed-commits", action="store_true",
                        help="tabulate finished cells of several code versions, each method named with its commit "
                             "(refused otherwise)")
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    cells = list(benchmark_cells())
    args = parser.parse_args(script_args(argv))
    if args.list_methods:
        print("\n".join(cells))
        return 0
    if not args.scenes or not args.out:
        parser.error("the following arguments are required: --scenes, --out")
    if args.trainings_per_gpu < 1:
        parser.error(f"--trainings-per-gpu {args.trainings_per_gpu}: give 1 or more")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    matrix = [(Path(s), seed, inp, m) for s in args.scenes for seed in args.seeds for inp in args.inpainters
              for m in args.methods]
    finished: dict[int, dict] = {}
    start, refused = time.perf_counter(), ""
    for k, (index, cell) in enumerate(run_matrix(matrix, args, out / "work"), 1):
        finished[index] = cell
        cells = [finished[i] for i in sorted(finished)]
        try:
            write_results(cells, out, args.mixed_commits)
        except MixedCommits as exc:  # the cells still run; the tables wait for one code
            refused = str(exc)
        bar = "#" * round(20 * k / len(matrix))
        detail = (f"m-PSNR {_fmt(cell['m_psnr'], 'm_psnr')} dB, {cell['seconds']} s" if cell["status"] == "done"
                  else f"{cell['status'].upper()}: {cell['reason']}")
        print(f"[{bar:<20}] {k}/{len(matrix)} {cell['scene']} seed {cell['seed']} {cell['method']}: {detail} "
              f"({time.perf_counter() - start:.0f} s so far)", flush=True)
    if refused:
        print(f"no tables: {refused}", flush=True)
        return 1
    try:  # the PNG once at the end: it takes an engine process
        run_engine(["chart", "--spec", str(out / "speed_accuracy.json"), "--out", str(out / "speed_accuracy.png")])
    except EngineError as exc:
        print(f"no PNG chart: {exc}", flush=True)
    pictures(cells, out, args.seeds[0])
    print(f"tables: {out / 'tables.md'}  results: {out / 'results.csv'}  pictures: {out / 'pictures'}", flush=True)
    return 0

