"""Where a training step's time goes: train a scene to a step (or resume a run), then profile steps.

    python benchmarks/train_profile.py --scene SCENE [--until 7000] [--steps 300] [--json OUT.json] [--save RUN]
    python benchmarks/train_profile.py --run RUN

Prints milliseconds per step (wall, CUDA synchronised at both ends only, as in training), then from
torch.profiler: kernels launched per step, GPU busy time per step (the sum of kernel times), host time
per step, the most expensive operators, and per part of a step (Trainer.step's named parts: data, render,
photometric, identity, regulariser, strategy, backward, optimizer) its host time and the GPU time of the
kernels it launched. A step that takes much longer than its GPU busy time is
bound by the host (Python and launches) or by waits (gsplat reads the number of tile intersections back
before it rasterizes). Engine Python; meant for the GPU machine.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import torch

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from engine.base.device import pick_device  # noqa: E402
from engine.base.versions import gpu_name  # noqa: E402
from engine.capture.scene import load_scene  # noqa: E402
from engine.formats.layout import RunLayout  # noqa: E402
from engine.train.config import TrainConfig  # noqa: E402
from engine.train.run import latest_checkpoint, save_checkpoint  # noqa: E402
from engine.train.trainer import Trainer, no_part  # noqa: E402


def trainer_from_args(args: argparse.Namespace) -> Trainer:
    if not args.run:
        config = TrainConfig(scene=args.scene, out="unused", max_gaussians=args.budget,
                             identity_every=args.identity_every, fused_ssim=args.fused_ssim).resolved()
        return Trainer(config, load_scene(config.scene), pick_device(config.device))
    config = TrainConfig(**json.loads(RunLayout(args.run).config_json.read_text()))
    config.steps = 10**9  # keep schedules where the checkpoint left them
    trainer = Trainer(config, load_scene(config.scene), pick_device(config.device))
    checkpoint = latest_checkpoint(Path(args.run))
    if checkpoint is not None:
        trainer.load_state_dict(torch.load(checkpoint, map_location="cpu", weights_only=False))
    return trainer


def synchronize() -> None:
    if torch.cuda.is_available():
        torch.cuda.synchronize()


def save_run(trainer: Trainer, run: Path) -> None:
    """A run folder `--run` (and older versions of this script) can resume: config.json and a checkpoint."""
    run.mkdir(parents=True, exist_ok=True)
    RunLayout(run).config_json.write_text(json.dumps(dataclasses.asdict(trainer.config), indent=1))
    save_checkpoint(run, trainer, keep=1)


def ms_per_step(trainer: Trainer, steps: int) -> float:
    synchronize()
    start = time.perf_counter()
    for _ in range(steps):
        trainer.step()
    synchronize()
    return (time.perf_counter() - start) / steps * 1000


PARTS = ("data", "render", "photometric", "identity", "regulariser", "strategy", "backward", "optimizer")


def parts(events, steps: int) -> dict:
    """Per named part of a step (Trainer.part, PARTS): calls, host milliseconds and the GPU milliseconds of the
    kernels it launched, each per step; a backward pass's kernels run in `backward`, whichever part built it."""
    out = {name: {"calls": 0.0, "host_ms": 0.0, "gpu_ms": 0.0} for name in PARTS}
    for e in events:
        if e.key not in out:
            continue
        if e.device_type == torch.autograd.DeviceType.CUDA:
            out[e.key]["gpu_ms"] += e.device_time_total / steps / 1000
        else:
            out[e.key]["calls"] += e.count / steps
            out[e.key]["host_ms"] += e.cpu_time_total / steps / 1000
    return {name: {k: round(v, 3) for k, v in row.items()} for name, row in out.items()}


def profile(trainer: Trainer, steps: int = 50) -> dict:
    activities = [torch.profiler.ProfilerActivity.CPU, torch.profiler.ProfilerActivity.CUDA]
    trainer.part = torch.profiler.record_function
    with torch.profiler.profile(activities=activities) as prof:
        for _ in range(steps):
            trainer.step()
        synchronize()
    trainer.part = no_part
    events = prof.key_averages()
    kernels = [e for e in events if e.device_type == torch.autograd.DeviceType.CUDA and not e.is_user_annotation]
    print(events.table(sort_by="cuda_time_total", row_limit=30))
    print(events.table(sort_by="cpu_time_total", row_limit=20))
    return {"kernels_per_step": sum(e.count for e in kernels) / steps,
            "gpu_busy_ms_per_step": sum(e.self_device_time_total for e in kernels) / steps / 1000,
            "parts": parts(events, steps),
            "top_kernels_ms_per_step": {e.key[:80]: round(e.self_device_time_total / steps / 1000, 3)
                                        for e in sorted(kernels, key=lambda e: -e.self_device_time_total)[:25]}}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--run", help="resume this run's newest checkpoint")
    source.add_argument("--scene", help="train this scene from its points to --until first")
    parser.add_argument("--until", type=int, default=7000, help="with --scene: steps to train before profiling")
    parser.add_argument("--budget", type=int, default=TrainConfig.max_gaussians)
    parser.add_argument("--identity-every", type=int, default=TrainConfig.identity_every)
    parser.add_argument("--fused-ssim", action="store_true", help="with --scene: the SSIM by fussim (a lead)")
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--json", help="write the numbers here")
    parser.add_argument("--save", help="with --scene: keep the trained state as a run folder here (for --run)")
    args = parser.parse_args()
    trainer = trainer_from_args(args)
    start = time.perf_counter()
    while args.scene and trainer.step_index < args.until:
        trainer.step()
    synchronize()
    print(f"trained to step {trainer.step_index} in {time.perf_counter() - start:.1f} s", flush=True)
    if args.save:
        save_run(trainer, Path(args.save))
    result = {"gaussians": len(trainer.params["means"]), "step": trainer.step_index,
              "gpu": gpu_name(trainer.device), "ms_per_step": round(ms_per_step(trainer, args.steps), 3)}
    result.update(profile(trainer))
    print(json.dumps(result, indent=1))
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
