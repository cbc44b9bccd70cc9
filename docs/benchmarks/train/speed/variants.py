"""Issue 17 item 2, exploration on the device: the same trainer, timed as it is and with one change at a time.

    PYTHONPATH=. python3 docs/benchmarks/train/speed/variants.py SCENE OUT.json [--until 7000]

Each variant runs 300 steps after 30 of warm-up, from where the previous one left off (the model keeps
training, so later variants see a few hundred steps more of it). Changes that only measure a cost
(`no_reg3d`, `no_noise`) are not candidates; `compiled_loss` and `cudnn_benchmark` are.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import torch

import engine.train.trainer as trainer_module
from engine.base.device import pick_device
from engine.base.versions import gpu_name
from engine.io.scene import load_scene
from engine.train.config import TrainConfig
from engine.train.trainer import Trainer

sys.path.insert(0, str(Path(__file__).resolve().parents[4] / "scripts"))
from profile_train import ms_per_step, profile, synchronize  # noqa: E402


def compiled_loss(trainer: Trainer) -> None:
    trainer_module.ssim = torch.compile(trainer_module.ssim)
    trainer_module.pixel_cross_entropy = torch.compile(trainer_module.pixel_cross_entropy)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("out")
    parser.add_argument("--until", type=int, default=7000)
    args = parser.parse_args()
    config = TrainConfig(scene=args.scene, out="unused").resolved()
    trainer = Trainer(config, load_scene(config.scene), pick_device("auto"))
    start = time.perf_counter()
    while trainer.step_index < args.until:
        trainer.step()
    synchronize()
    results = {"train_to_until_s": round(time.perf_counter() - start, 1), "gaussians": len(trainer.params["means"]),
               "gpu": gpu_name(trainer.device), "base": ms_per_step(trainer, 300)}
    results["profile"] = profile(trainer)
    reg3d, noise = trainer.config.reg3d_every, trainer_module.BudgetStrategy.step_post_backward
    trainer.config.reg3d_every = 0
    results["no_reg3d"] = ms_per_step(trainer, 300)
    trainer.config.reg3d_every = reg3d
    trainer_module.BudgetStrategy.step_post_backward = lambda *a, **k: None
    results["no_noise_no_relocation"] = ms_per_step(trainer, 300)
    trainer_module.BudgetStrategy.step_post_backward = noise
    torch.backends.cudnn.benchmark = True
    ms_per_step(trainer, 30)
    results["cudnn_benchmark"] = ms_per_step(trainer, 300)
    torch.backends.cudnn.benchmark = False
    start = time.perf_counter()
    compiled_loss(trainer)
    ms_per_step(trainer, 30)
    results["compile_s"] = round(time.perf_counter() - start, 1)
    results["compiled_loss"] = ms_per_step(trainer, 300)
    print(json.dumps(results, indent=1))
    Path(args.out).write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
