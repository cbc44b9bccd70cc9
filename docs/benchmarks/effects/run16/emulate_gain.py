"""Why the GPU livingroom's relit shadow overshoots gt/ (docs/BENCHMARKS.md, run 3): find_shadow run on the 640
scene's exact data, which has no trained Gaussians here. The views' samples are lifted with the generator's
depth/, the object's points come from its masked pixels, and the support's samples stand in for the remaining
Gaussians. Prints the shadow's gain against the truth (gt/ over images/ inside effects/, pixel by pixel), then
what residual_gain would ask for after the samples were relit exactly by that gain. `exact_search` is that set-up
and search, for the other exact-data probes (run18/gain_samples.py).

    PYTHONPATH=. python docs/benchmarks/effects/run16/emulate_gain.py .bench/640/livingroom_s0
"""

import math
import sys
from types import SimpleNamespace

import cv2
import numpy as np
import torch

from engine.edit.effects import EffectsConfig, Samples, _darkness, find_shadow, residual_gain
from engine.edit.support_plane import object_support
from engine.formats.cameras import backproject, mean_up
from engine.io.scene import load_scene


def exact_search(scene_dir: str) -> SimpleNamespace:
    """The scene (with depth), the samples of every other training view, the object's points, the support's
    samples standing in for the remaining Gaussians, the support plane and find_shadow's search on them."""
    scene = load_scene(scene_dir, depth=True)
    tid = scene.target.id
    views = scene.train[::2]
    cams = [scene.cameras[i] for i in views]
    regions = [scene.masks[i] == tid for i in views]
    samples = Samples.from_views(cams, [scene.images[i] for i in views], [scene.depths[i] for i in views], regions)
    obj = []
    for i in views:
        ys, xs = np.nonzero(scene.masks[i] == tid)
        obj.append(backproject(scene.cameras[i], xs + 0.5, ys + 0.5, scene.depths[i][ys, xs]))
    obj = np.concatenate(obj)
    obj = obj[np.random.default_rng(0).choice(len(obj), 20000, replace=False)]
    up = mean_up(np.stack([c.R for c in scene.cameras]))
    pts = samples.points[np.random.default_rng(1).choice(len(samples.points), 150000, replace=False)]
    n = len(pts)
    remaining = {"means": torch.as_tensor(pts, dtype=torch.float32),
                 "quats": torch.tensor([[1.0, 0, 0, 0]]).repeat(n, 1), "scales": torch.full((n, 3), math.log(0.003)),
                 "opacities": torch.full((n,), 3.0), "sh0": torch.zeros(n, 1, 3), "shN": torch.zeros(n, 15, 3),
                 "identity": torch.zeros(n, 16)}
    plane = object_support(pts, obj, up)
    search = find_shadow(remaining, obj, plane, samples, EffectsConfig())
    return SimpleNamespace(scene=scene, samples=samples, obj=obj, plane=plane, search=search)


def main(scene_dir: str) -> None:
    found = exact_search(scene_dir)
    scene, samples, search = found.scene, found.samples, found.search
    print(search.verdict, search.report())
    ratios = []
    for i in scene.test:
        effects = cv2.imread(f"{scene_dir}/effects/{scene.cameras[i].name}", 0)
        if i in scene.gt_images and effects is not None:
            e = effects > 127
            ratios.append((scene.gt_images[i][e].astype(float) + 1) / (scene.images[i][e].astype(float) + 1))
    print("true gain (gt/ over images/ in effects/), percentiles 25/50/75:",
          np.percentile(np.concatenate(ratios), [25, 50, 75], axis=0).round(3).tolist())
    shadow = search.shadow
    if shadow is not None:
        print("gain", shadow.gain.round(3))
        picked = samples.points[shadow.pick]
        darkness = _darkness(picked, picked, shadow.dark)
        relit = samples.colors.copy()
        relit[shadow.pick] = samples.colors[shadow.pick] * (1 + darkness[:, None] * (shadow.gain[None] - 1))
        residual = residual_gain(shadow, samples, Samples(samples.points, relit))
        print("residual after an exact relight of the samples", residual.round(3))


if __name__ == "__main__":
    main(sys.argv[1])
