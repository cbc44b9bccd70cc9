"""What the pale sheets left where the statue's plinth stood are: the Gaussians removal kept that lie in front of
the true background inside the object's region of a test view (the generator's gt_depth/, the scene without
the object), against the ones removal took.

For each kept Gaussian that projects into a test view's object region at least `AHEAD` nearer than gt_depth
there ("in front": nothing should be there once the object is gone), its object probability (the identity
rule takes > 0.3), the share of the training views framing it whose dilated object mask it falls in (the
visual hull takes >= 0.9), its opacity, largest scale and distance from the support plane. Written as JSON.

    python ghost.py RUN OBJECT OUT.json      (after `engine remove`, which writes the support plane)
"""

import json
import sys
from pathlib import Path

import numpy as np
import torch

from engine.edit.removal import RemovalConfig, object_probability, select
from engine.formats.cameras import project, sample_nearest
from engine.io.masks import dilate
from engine.io.scene import load_scene
from engine.train.trained_run import load_run

AHEAD = 0.02  # of the background's depth
QUANTILES = (0.1, 0.5, 0.9)


def hull_share(means: np.ndarray, run, object_id: int, pixels: int = 2) -> np.ndarray:
    framed, inside = np.zeros(len(means)), np.zeros(len(means))
    for i in run.scene.train:
        u, v, z = project(run.scene.cameras[i], means)
        hit, in_frame = sample_nearest(dilate(run.scene.masks[i] == object_id, pixels), u, v)
        in_frame &= z > 0
        framed += in_frame
        inside += in_frame & hit
    return inside / np.maximum(framed, 1)


def summary(values: np.ndarray) -> dict:
    if len(values) == 0:
        return {}
    return {f"q{int(q * 100)}": round(float(np.quantile(values, q)), 4) for q in QUANTILES}


run_dir, name, out = Path(sys.argv[1]), sys.argv[2], Path(sys.argv[3])
run = load_run(run_dir)
gt_depths = load_scene(run.scene.root, depth=True).gt_depths  # load_run reads no depth; root is at the run's size
obj = run.scene.object_by(name)
chosen, counts = select(run, RemovalConfig(run=str(run_dir), object=name))
g = run.gaussians
means = g["means"].numpy()
ahead = np.zeros(len(means), dtype=bool)
for i in run.scene.test:
    background = gt_depths.get(i)
    if background is None:
        continue
    u, v, z = project(run.scene.cameras[i], means)
    depth, in_frame = sample_nearest(background, u, v)
    region, _ = sample_nearest(run.scene.masks[i] == obj.id, u, v)
    ahead |= in_frame & region & (z > 0) & (z < (1 - AHEAD) * depth)
kept_ahead = ahead & ~chosen
plane = json.loads((run_dir / "removed" / "removal.json").read_text()).get("support_plane")
features = {
    "object_probability": object_probability(g["identity"], run.classifier, obj.id).numpy(),
    "hull_share": hull_share(means, run, obj.id),
    "opacity": torch.sigmoid(g["opacities"]).numpy(),
    "largest_scale": torch.exp(g["scales"]).max(dim=1).values.numpy(),
}
if plane:
    features["above_plane"] = means @ np.array(plane[:3]) + plane[3]
report = {"counts": counts, "removed": int(chosen.sum()), "kept_in_front_of_the_background": int(kept_ahead.sum()),
          "removed_in_front_of_the_background": int((ahead & chosen).sum()),
          "kept": {k: summary(v[kept_ahead]) for k, v in features.items()},
          "removed_ones": {k: summary(v[chosen]) for k, v in features.items()},
          "kept_opaque_over_0.3": int((kept_ahead & (features["opacity"] > 0.3)).sum()),
          "kept_over_1cm_above_the_plane": int((kept_ahead & (features.get("above_plane", 1.0) > 0.01)).sum()),
          "kept_with_hull_share_0.5_to_0.9": int((kept_ahead & (features["hull_share"] >= 0.5)
                                                   & (features["hull_share"] < 0.9)).sum())}
out.write_text(json.dumps(report, indent=1))
print(json.dumps(report, indent=1))
