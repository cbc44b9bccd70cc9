"""Train a scene from its points to a step and keep the state as a run folder, with whatever engine is first on
PYTHONPATH (call2.sh runs it with the code before the host-side savings, so both versions resume its checkpoint).

    python3 train_to.py SCENE STEPS RUN
"""

import dataclasses
import json
import sys
import time
from pathlib import Path

import torch

from engine.formats.layout import RunLayout
from engine.io.scene import load_scene
from engine.train.config import TrainConfig
from engine.train.run import save_checkpoint
from engine.train.trainer import Trainer

scene, steps, run = sys.argv[1], int(sys.argv[2]), Path(sys.argv[3])
config = TrainConfig(scene=scene, out=str(run)).resolved()
trainer = Trainer(config, load_scene(scene), torch.device("cuda"))
start = time.perf_counter()
while trainer.step_index < steps:
    trainer.step()
torch.cuda.synchronize()
print(f"trained to step {steps} in {time.perf_counter() - start:.1f} s, {len(trainer.params['means'])} Gaussians")
run.mkdir(parents=True)
RunLayout(run).config_json.write_text(json.dumps(dataclasses.asdict(config), indent=1))
save_checkpoint(run, trainer, keep=1)
