"""Benchmark Gaussian Grouping training: wall time, steps/s, peak GPU memory, Gaussians, PSNR/SSIM, mIoU.

    python benchmarks/train_speed.py --scenes DIR... --budgets 0 300000 [--steps 30000] --results DIR [--runs DIR]
    python benchmarks/train_speed.py --report [--results DIR]                      # DIR/*.json -> DIR/tables.md

Each run writes one JSON (machine, commit, command, settings, numbers) into --results (default
docs/results/train/) and --report makes its tables.md. Engine Python; absolute times only count
when measured on the GPU machine. Budget 0 means none (gsplat DefaultStrategy).
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

RESULTS = ALL_RESULTS / "train"


def warm_up() -> None:
    """Build and load gsplat's CUDA code before any clock starts: its first call compiles it (about 40 s on
    a fresh machine, cached afterwards), which is set-up, not training."""
    import torch

    if not torch.cuda.is_available():
        return
    from gsplat import rasterization

    one = torch.ones(1, 3, device="cuda")
    rasterization(one * torch.tensor([0, 0, 2.0], device="cuda"), torch.tensor([[1.0, 0, 0, 0]], device="cuda"),
                  one * 0.1, torch.ones(1, device="cuda"), one, torch.eye(4, device="cuda")[None],
                  torch.tensor([[[50.0, 0, 16], [0, 50, 16], [0, 0, 1]]], device="cuda"), 32, 32)
    torch.cuda.synchronize()


def run_one(scene: Path, budget: int, steps: int, results: Path, runs: Path | None, fused_ssim: bool = False,
            identity_every: int = 0, views_per_step: int = 0) -> dict:
    """One training of `steps` views' worth (at `views_per_step` views a step: steps / B steps; 0: as many as
    `engine train` takes at the default's length and this budget, TrainConfig.auto_views), timed."""
    import torch

    from engine.train.config import TrainConfig
    from engine.train.run import train

    views_per_step = views_per_step or TrainConfig(max_gaussians=budget).auto_views()
    with tempfile.TemporaryDirectory() as tmp:
        torch.cuda.reset_peak_memory_stats() if torch.cuda.is_available() else None
        start = time.perf_counter()
        name = (f"{scene.name}_{budget or 'none'}" + ("_fused_ssim" if fused_ssim else "")
                + (f"_identity_every_{identity_every}" if identity_every else "")
                + (f"_views_{views_per_step}" if views_per_step > 1 else ""))
        out = (runs or Path(tmp)) / name
        config = TrainConfig(scene=str(scene), out=str(out), steps=steps // views_per_step, max_gaussians=budget,
                             fused_ssim=fused_ssim, identity_every=identity_every or TrainConfig.identity_every,
                             views_per_step=views_per_step)
        metrics = train(config)
        wall = time.perf_counter() - start
    miou = metrics["identity_miou"]  # None for a scene without masks
    record = {
        "scene": scene.name, "budget": budget or None, "steps": config.steps, "wall_s": round(wall, 1),
        "train_s": metrics["train_seconds"], "steps_per_s": round(config.steps / metrics["train_seconds"], 1),
        "views_per_step": views_per_step,
        "peak_gpu_mb": metrics["peak_gpu_mb"], "gaussians": metrics["gaussians"], "psnr": round(metrics["psnr"], 2),
        "ssim": round(metrics["ssim"], 4), "identity_miou": miou and round(miou, 3), "fused_ssim": fused_ssim,
        "identity_every": config.identity_every,
        **provenance(),
    }
    save_record(results, name, record)
    return record


def report(results: Path) -> None:
    from engine.train.config import TrainConfig

    records, usual = load_records(results), TrainConfig.identity_every
    lines = ["| scene | budget | steps | training loop | steps/s | peak GPU MB | Gaussians | test PSNR | SSIM "
             "| id mIoU "
             "| device |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(records, key=lambda r: (r["scene"], r["budget"] or 10**12)):
        scene = (r["scene"] + (" (fused SSIM)" if r.get("fused_ssim") else "")
                 + (f" (identities every {r['identity_every']})" if r.get("identity_every", usual) != usual else "")
                 + (f" ({r['views_per_step']} views a step)" if r.get("views_per_step", 1) > 1 else ""))
        lines.append(f"| {scene} | {r['budget'] or 'none'} | {r['steps']} | {r['train_s'] / 60:.1f} min | "
                     f"{r['steps_per_s']} | {r['peak_gpu_mb']} | {r['gaussians']:,} | {r['psnr']} | {r['ssim']} | "
                     f"{r['identity_miou']} | {r['device']} |")
    commands = sorted({r["command"] for r in records})
    write_tables(results, "Training speed and quality", [*lines, "", "Commands:", *[f"- `{c}`" for c in commands]])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", nargs="*", default=[])
    parser.add_argument("--budgets", type=int, nargs="*", default=[0, 300_000])
    parser.add_argument("--steps", type=int, default=30_000)
    parser.add_argument("--runs", help="keep the run folders here (default: a temporary folder)")
    parser.add_argument("--fused-ssim", action="store_true", help="the SSIM by fussim's kernel (a lead)")
    parser.add_argument("--identity-every", type=int, default=0,
                        help="identities rendered every Nth step (0: the default's; a lead: the profile's identity "
                             "steps cost 2.4 ms against 1.5 for the others)")
    parser.add_argument("--views-per-step", type=int, default=0,
                        help="views a training step renders (gsplat's batch; 0: the engine's default, 4 at a budget); "
                             "the run takes STEPS / B steps")
    return report_or_measure(parser, RESULTS, report, measure)


def measure(args: argparse.Namespace) -> None:
    warm_up()
    for scene in args.scenes:
        for budget in args.budgets:
            run_one(Path(scene), budget, args.steps, Path(args.results), Path(args.runs) if args.runs else None,
                    args.fused_ssim, args.identity_every, args.views_per_step)


if __name__ == "__main__":
    sys.exit(main())
