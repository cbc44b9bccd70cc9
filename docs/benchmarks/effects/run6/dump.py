"""Dump what the hole masks and the shadow search weigh on a trained run, for CPU diagnosis elsewhere."""

import sys

import numpy as np

from engine.base.device import pick_device
from engine.edit.effects import Samples
from engine.edit.removal import RemovalConfig, keep, select
from engine.edit.support_plane import object_core, object_support
from engine.formats.cameras import mean_up
from engine.render.render_views import render_pictures
from engine.train.trained_run import load_run

run_dir, obj_name, out = sys.argv[1:4]
run = load_run(run_dir)
device = pick_device(sys.argv[4] if len(sys.argv) > 4 else "cuda")
scene = run.scene
removed, _ = select(run, RemovalConfig(run=run_dir, object=obj_name))
remaining, gone = keep(run.gaussians, removed), keep(run.gaussians, ~removed)
up = mean_up(np.stack([c.R for c in scene.cameras]))
core = object_core(gone, up)
plane = object_support(remaining["means"].numpy(), core, up)
train = scene.train
orig = list(render_pictures(run.gaussians, [scene.cameras[i] for i in train], run.sh_degree, device))
after = list(render_pictures(remaining, scene.cameras, run.sh_degree, device))
obj = scene.object_by(obj_name)
regions = [scene.masks[i] == obj.id for i in train]
samples = Samples.from_views(
    [scene.cameras[i] for i in train], [after[i].rgb for i in train], [after[i].depth for i in train], regions
)
np.savez_compressed(
    out + "_shadow.npz",
    core=core.astype(np.float32),
    plane_n=plane[0],
    plane_d=plane[1],
    points=samples.points.astype(np.float32),
    colors=samples.colors.astype(np.float16),
    remaining_means=remaining["means"].numpy().astype(np.float32),
)
np.savez_compressed(
    out + "_depth.npz",
    train=np.array(train),
    orig=np.stack([p.depth for p in orig]).astype(np.float16),
    after=np.stack([p.depth for p in after]).astype(np.float16),
)
print("dumped", len(core), samples.points.shape, plane)
