"""Where a training step's time goes: resume a run's newest checkpoint and profile a few steps.

    python scripts/profile_train.py --run RUN [--steps 200]

Prints milliseconds per step (wall, with CUDA synchronised) and torch.profiler's table of the most
expensive operators. Engine Python; meant for the GPU machine.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import torch

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from engine.base.device import pick_device  # noqa: E402
from engine.formats.layout import RunLayout  # noqa: E402
from engine.io.scene import load_scene  # noqa: E402
from engine.train.config import TrainConfig  # noqa: E402
from engine.train.run import latest_checkpoint  # noqa: E402
from engine.train.trainer import Trainer  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", required=True)
    parser.add_argument("--steps", type=int, default=200)
    args = parser.parse_args()
    run = Path(args.run)
    config = TrainConfig(**json.loads(RunLayout(run).config_json.read_text()))
    config.steps = 10**9  # keep schedules where the checkpoint left them
    trainer = Trainer(config, load_scene(config.scene), pick_device(config.device))
    checkpoint = latest_checkpoint(run)
    if checkpoint is not None:
        trainer.load_state_dict(torch.load(checkpoint, map_location="cpu", weights_only=False))
    for _ in range(20):
        trainer.step()
    torch.cuda.synchronize()
    start = time.perf_counter()
    for _ in range(args.steps):
        trainer.step()
    torch.cuda.synchronize()
    print(f"{len(trainer.params['means'])} Gaussians at step {trainer.step_index}: "
          f"{(time.perf_counter() - start) / args.steps * 1000:.2f} ms/step")
    activities = [torch.profiler.ProfilerActivity.CPU, torch.profiler.ProfilerActivity.CUDA]
    with torch.profiler.profile(activities=activities) as prof:
        for _ in range(50):
            trainer.step()
        torch.cuda.synchronize()
    print(prof.key_averages().table(sort_by="cuda_time_total", row_limit=25))
    print(prof.key_averages().table(sort_by="cpu_time_total", row_limit=15))
    return 0


if __name__ == "__main__":
    sys.exit(main())
