"""The darkening relight judged on one training without retraining: its removed renders (shadow relit, no
darkening yet; dumped by dump5.py) lifted to 3D with their depth, each test-view pixel multiplied by the gain
find_contact_shade gives its surface point, and scored outside the true hole against gt/.

Run from the repository root: PYTHONPATH=. python docs/benchmarks/effects/run7/proxy.py SCENE DUMPDIR [k=v ...]
(SCENE under .bench/, DUMPDIR holding SCENE_dump.npz and SCENE/ from the tar; reach=X sets contact_reach,
other k=v go to find_contact_shade). The numbers in docs/BENCHMARKS.md ran with reach passed as an argument.
"""

import dataclasses
import sys
from pathlib import Path

import cv2
import numpy as np
import torch

from engine.edit.contact_shade import find_contact_shade
from engine.edit.effects import EffectsConfig, Samples
from engine.formats.cameras import backproject, pixel_grid
from engine.io.scene import load_scene

name, dumps = sys.argv[1], Path(sys.argv[2])
options = {k: float(v) if "." in v else int(v) for k, v in (a.split("=") for a in sys.argv[3:])}
config = dataclasses.replace(EffectsConfig(), contact_reach=options.pop("reach", EffectsConfig().contact_reach))
scene = load_scene(Path(".bench") / name)
removed = dumps / name
dump = np.load(dumps / f"{name}_dump.npz")
depth = dump["depth"].astype(np.float32)
plane, core = (dump["plane"][:3], float(dump["plane"][3])), dump["core"]


def image(i: int) -> np.ndarray:
    return cv2.imread(str(removed / "images" / scene.cameras[i].name))[..., ::-1].copy()


def mask(folder: str, i: int) -> np.ndarray:
    return cv2.imread(str(removed / folder / scene.cameras[i].name), 0) > 127


train = scene.train
shown = Samples.from_views([scene.cameras[i] for i in train], [image(i) for i in train], [depth[i] for i in train],
                           [np.zeros_like(mask("masks", i)) for i in train])
before = after = 0.0
recall, precision = [], []
for i in scene.test:
    camera, rgb, truth = scene.cameras[i], image(i) / 255.0, scene.gt_images[i] / 255.0
    u, v = pixel_grid(camera)
    ok = np.isfinite(depth[i]) & (depth[i] > 0)
    points = torch.from_numpy(backproject(camera, u[ok], v[ok], depth[i][ok]).astype(np.float32))
    found = find_contact_shade({"means": points}, core, plane, shown, config, **options)
    relit, weight = rgb.copy(), np.zeros(ok.shape)
    if found is not None:
        gains, shares = np.ones((ok.sum(), 3)), np.zeros(ok.sum())
        gains[found.shaded], shares[found.shaded] = found.gains, found.weight
        relit[ok], weight[ok] = np.clip(rgb[ok] * gains, 0, 1), shares
    outside = ~scene.holes[i]
    before += ((rgb - truth) ** 2)[outside].mean()
    after += ((relit - truth) ** 2)[outside].mean()
    near = cv2.dilate(mask("masks", i).astype(np.uint8), np.ones((3, 3))).astype(bool)
    estimate, effects = (mask("effects", i) | (weight >= 0.5)) & ~near, scene.effects[i]
    if effects.sum():
        recall.append((estimate & effects).sum() / effects.sum())
    if estimate.sum():
        precision.append((estimate & effects).sum() / estimate.sum())
n = len(scene.test)
print(name, options, "outside the hole", round(-10 * np.log10(before / n), 2), "->",
      round(-10 * np.log10(after / n), 2), "effect recall", round(float(np.mean(recall)), 3),
      "precision", round(float(np.mean(precision)), 3))
