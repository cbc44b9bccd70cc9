"""Dump a removed run for CPU design: every view's removed render, depth, region, our effects and holes,
the remaining Gaussians (centre, base colour, opacity, size) and the object's core and support plane."""

import json
import sys
import tarfile
from pathlib import Path

import numpy as np

from engine.edit.effects import colors_of
from engine.edit.removal import RemovalConfig, keep, select
from engine.edit.support_plane import object_core
from engine.formats.cameras import mean_up
from engine.io.image_io import exr_name, read_depth
from engine.io.ply_io import load_ply
from engine.train.trained_run import load_run

run_dir, out = Path(sys.argv[1]), sys.argv[2]
run = load_run(run_dir)
report = json.loads((run_dir / "removed/removal.json").read_text())
obj = report["config"]["object"]
removed, _ = select(run, RemovalConfig(run=str(run_dir), object=obj))
gone = keep(run.gaussians, ~removed)
remaining = load_ply(run_dir / "removed/point_cloud.ply")  # relit
scene = run.scene
core = object_core(gone, mean_up(np.stack([c.R for c in scene.cameras])))
depth = np.stack([read_depth(run_dir / "removed/depth" / exr_name(c.name)) for c in scene.cameras])
g = remaining
np.savez_compressed(out + "_dump.npz", core=core.astype(np.float32), plane=np.array(report["support_plane"]),
                    depth=depth.astype(np.float16), means=g["means"].numpy().astype(np.float32),
                    colors=colors_of(g).astype(np.float16),
                    opacity=(1 / (1 + np.exp(-g["opacities"].numpy()))).astype(np.float16),
                    scales=np.exp(g["scales"].numpy()).astype(np.float16))
with tarfile.open(out + "_removed.tar", "w") as tar:
    for sub in ("images", "masks", "effects"):
        tar.add(run_dir / "removed" / sub, arcname=sub)
    tar.add(run_dir / "holes", arcname="holes")
    tar.add(run_dir / "removed/removal.json", arcname="removal.json")
print("dumped", len(core), depth.shape)
