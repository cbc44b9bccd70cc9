"""Removal variants on a trained run (visual hull on/off, its dilation): PSNR outside the true hole and on
the revealed part, crops of the removed renders beside input and gt, and the Gaussians near the object."""

import json
import sys

import cv2
import numpy as np

from engine.edit.removal import RemovalConfig, object_probability, run_removal, select
from engine.io.image_io import read_png
from engine.train.trained_run import load_run

run_dir, obj_name, out = sys.argv[1:4]
DEV = sys.argv[4] if len(sys.argv) > 4 else "cuda"
variants = {
    "hull2": dict(hull=True, hull_dilate=2),
    "hull0": dict(hull=True, hull_dilate=0),
    "nohull": dict(hull=False),
}
res = {}
for name, kw in variants.items():
    r = run_removal(RemovalConfig(run=run_dir, object=obj_name, out=f"/tmp/r/rm_{name}", device=DEV, **kw))
    res[name] = {k: r[k] for k in ("removed", "selected_by", "psnr_outside_hole", "psnr_revealed")}
    print("VARIANT", name, res[name], flush=True)
json.dump(res, open(f"{out}_hullvar.json", "w"), indent=1)
run = load_run(run_dir)
scene = run.scene
obj = scene.object_by(obj_name)
rows = []
for i in scene.test[:5]:
    cam = scene.cameras[i]
    m = scene.masks[i] == obj.id
    ys, xs = np.nonzero(m)
    y0, y1, x0, x1 = max(ys.min() - 10, 0), ys.max() + 10, max(xs.min() - 10, 0), xs.max() + 10
    panels = [scene.images[i], scene.gt_images[i]] + [read_png(f"/tmp/r/rm_{n}/images/{cam.name}") for n in variants]
    rows.append(np.concatenate([p[y0:y1, x0:x1] for p in panels], 1))
w = max(r.shape[1] for r in rows)
rows = [np.pad(r, ((0, 4), (0, w - r.shape[1]), (0, 0))) for r in rows]
cv2.imwrite(f"{out}_removed_crops.png", cv2.cvtColor(np.concatenate(rows, 0), cv2.COLOR_RGB2BGR))
# the Gaussians near the object, for CPU analysis
g = run.gaussians
means = g["means"].numpy()
chosen, _ = select(run, RemovalConfig(run=run_dir, object=obj_name))
prob = object_probability(g["identity"], run.classifier, obj.id).numpy()
c = np.median(means[chosen], 0)
r = np.percentile(np.linalg.norm(means[chosen] - c, axis=1), 95)
near = np.linalg.norm(means - c, axis=1) < 2.5 * r
np.savez_compressed(
    f"{out}_near.npz",
    means=means[near],
    sh0=g["sh0"][near].numpy(),
    opac=g["opacities"][near].numpy(),
    scales=g["scales"][near].numpy(),
    quats=g["quats"][near].numpy(),
    prob=prob[near],
    chosen=chosen[near],
)
print("near", near.sum())
