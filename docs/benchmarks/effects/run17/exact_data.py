"""The 640 scenes' exact data standing in for a trained removal (emulate_contact.py; run18/penumbra.py at
df969a4): the test views' pixels outside the target's region, lifted with the generator's depth/, are the remaining
Gaussians and the views' samples at once; gt/ at the same pixels is the truth; the target's pixels, lifted, are its
Gaussians."""

import math
from types import SimpleNamespace

import numpy as np
import torch

from engine.edit.effects import Samples
from engine.formats.cameras import backproject, mean_up
from engine.io.scene import load_scene


def exact_data(scene_dir: str) -> SimpleNamespace:
    scene = load_scene(scene_dir, depth=True)
    tid = scene.target.id
    views = [i for i in scene.test if i in scene.gt_images]
    cams = [scene.cameras[i] for i in views]
    regions = [scene.masks[i] == tid for i in views]
    depths = [scene.depths[i] for i in views]

    def flags(select) -> np.ndarray:
        """(N,) bool over the samples: the pixels `select(view)` (a bool mask per view) marks, lifted alike."""
        labels = [np.repeat(select(i)[..., None], 3, axis=2) * 255.0 for i in views]
        return Samples.from_views(cams, labels, depths, regions, most=300_000).colors[:, 0] > 0.5

    samples = Samples.from_views(cams, [scene.images[i] for i in views], depths, regions, most=300_000)
    truth = Samples.from_views(cams, [scene.gt_images[i] for i in views], depths, regions, most=300_000).colors
    lifted = []
    for i in views:
        ys, xs = np.nonzero((scene.masks[i] == tid) & np.isfinite(scene.depths[i]))
        lifted.append(backproject(scene.cameras[i], xs + 0.5, ys + 0.5, scene.depths[i][ys, xs]))
    obj = np.concatenate(lifted)
    obj = obj[np.random.default_rng(0).choice(len(obj), min(len(obj), 20000), replace=False)]
    pts = samples.points
    n = len(pts)
    remaining = {"means": torch.as_tensor(pts, dtype=torch.float32),
                 "quats": torch.tensor([[1.0, 0, 0, 0]]).repeat(n, 1), "scales": torch.full((n, 3), math.log(0.003)),
                 "opacities": torch.full((n,), 3.0), "sh0": torch.zeros(n, 1, 3), "shN": torch.zeros(n, 15, 3),
                 "identity": torch.zeros(n, 16)}
    # which samples show another object (the cup, box, apple, sharpener)
    is_theirs = flags(lambda i: (scene.masks[i] != tid) & (scene.masks[i] != 0))
    return SimpleNamespace(scene=scene, samples=samples, truth=truth, obj=obj, pts=pts, n=n, remaining=remaining,
                           is_theirs=is_theirs, up=mean_up(np.stack([c.R for c in scene.cameras])), flags=flags)


def db(a: np.ndarray, b: np.ndarray) -> float:
    return round(float(10 * np.log10(1.0 / max(float(((a - b) ** 2).mean()), 1e-12))), 2)
