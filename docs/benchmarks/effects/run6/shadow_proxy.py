"""find_shadow fed exact geometry (the generator's depth) instead of a trained run: does the search find the
tabletop's shadow at all, and which test turns it down?"""

import sys
from pathlib import Path

import numpy as np
import torch

from engine.edit import effects as E
from engine.edit.support_plane import object_support
from engine.formats.cameras import backproject, mean_up, pixel_grid
from engine.io.scene import load_scene

scene = load_scene(Path(sys.argv[1]), depth=True)
tid = scene.target.id
train = scene.train
cams = [scene.cameras[i] for i in train]
regions = [scene.masks[i] == tid for i in train]
depths = [scene.depths[i] for i in train]
up = mean_up(np.stack([c.R for c in scene.cameras]))
objp, rest = [], []
for c, r, d in zip(cams, regions, depths, strict=False):
    u, v = pixel_grid(c)
    ok = np.isfinite(d)
    objp.append(backproject(c, u[r & ok], v[r & ok], d[r & ok]))
    m = ~r & ok
    rest.append(backproject(c, u[m], v[m], d[m])[::7])
obj = np.concatenate(objp)[::5]
means = np.concatenate(rest)
plane = object_support(means, obj, up)
print("plane", plane, "obj", len(obj))
samples = E.Samples.from_views(cams, [scene.images[i] for i in train], depths, regions)
frame = E._Frame.of(*plane)
size = float(np.percentile(frame.height(obj), 98) - np.percentile(frame.height(obj), 2))
print("size", size)
cfg = E.EffectsConfig(**{k: float(v) for k, v in (a.split("=") for a in sys.argv[2:])})
gauss = {"means": torch.from_numpy(means).float()}
# replicate the search to print scores
orig_chance = E._chance_contrast


def chance(*a):
    v = orig_chance(*a)
    print("chance contrast", round(v, 3), "light", a[2])
    return v


E._chance_contrast = chance
orig_missing = E._missing_light
best = {"v": -1e9}


def missing(inside, log_y, darker):
    v = orig_missing(inside, log_y, darker)
    if v > best["v"]:
        best["v"] = v
        best["inside"] = int(inside.sum())
    return v


E._missing_light = missing
s = E.find_shadow(gauss, obj, plane, samples, cfg)
print("best coverage", best)
print("shadow", None if s is None else s.report())
