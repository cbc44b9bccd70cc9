import sys
from pathlib import Path

import numpy as np
import torch

from engine.base.knn import knn
from engine.edit import effects as E
from engine.formats.cameras import backproject, pixel_grid
from engine.io.scene import load_scene

name, scene_dir = sys.argv[1], sys.argv[2]
d = np.load(f"/tmp/s4/d/{name}_shadow.npz")
plane = (d["plane_n"].astype(np.float64), float(d["plane_d"]))
samples = E.Samples(d["points"].astype(np.float64), d["colors"].astype(np.float64))
core = d["core"].astype(np.float64)
search = E.find_shadow({"means": torch.from_numpy(d["remaining_means"])}, core, plane, samples, E.EffectsConfig())
print(search.report())
# true shadow points: test views' effects masks lifted with the exact depth
scene = load_scene(Path(scene_dir), depth=True)
truth = []
for i in scene.test:
    if i in scene.effects:
        c = scene.cameras[i]
        u, v = pixel_grid(c)
        m = scene.effects[i] & np.isfinite(scene.depths[i])
        truth.append(backproject(c, u[m], v[m], scene.depths[i][m]))
truth = np.concatenate(truth)
frame = E._Frame.of(*plane)
print("truth shadow points", len(truth), f"height above plane: median {np.median(frame.height(truth)):.4f}")
dist, _ = knn(torch.as_tensor(samples.points, dtype=torch.float32), torch.as_tensor(truth, dtype=torch.float32), 1)
in_true = dist[:, 0].numpy() ** 0.5 < 0.005 if False else dist[:, 0].numpy() < 0.005
log_y = np.log(samples.colors @ E.LUMA + 1e-3)
print(
    "samples in true shadow",
    in_true.sum(),
    f"median log_y in {np.median(log_y[in_true]):.3f}, out {np.median(log_y[~in_true]):.3f}",
)
np.save(f"/tmp/s4/{name}_in_true.npy", in_true)
