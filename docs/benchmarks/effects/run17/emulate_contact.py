"""Run 4's two suspects for the GPU livingroom's 29.5 dB outside the hole, tried on the 640 scene's exact data
(no trained Gaussians here, as run16/emulate_gain.py): the test views' pixels of the support are lifted with the
generator's depth/ and stand in for the remaining Gaussians, relit by the cast shadow's gain the search finds on
them, then by the contact shade's variants; each is scored against gt/ at the same pixels, where the relights
changed something (PSNR over those samples, their relit / gt/ ratio per channel, 25th / 50th / 75th percentile).

    PYTHONPATH=. python docs/benchmarks/effects/run17/emulate_contact.py .bench/640/livingroom_s0

Variants of the contact shade: as today (per-channel gain from a 5-cell window); one grey gain (the darkening's
luminance, all channels alike); windows of 9 and 13 cells. And of the cast shadow: the support in the other
objects' own cast shadows (along the light found) left unlit, with and without the grey contact gain.
"""

import math
import sys

import numpy as np
import torch

from engine.edit.contact_shade import find_contact_shade
from engine.edit.effects import LUMA, EffectsConfig, Samples, find_shadow, their_shadows
from engine.edit.plane_grid import Site
from engine.edit.support_plane import object_support
from engine.formats.cameras import backproject, mean_up
from engine.io.scene import load_scene

scene = load_scene(sys.argv[1], depth=True)
tid = scene.target.id
views = [i for i in scene.test if i in scene.gt_images]
cams = [scene.cameras[i] for i in views]
regions = [scene.masks[i] == tid for i in views]
depths = [scene.depths[i] for i in views]
samples = Samples.from_views(cams, [scene.images[i] for i in views], depths, regions, most=300_000)
truth = Samples.from_views(cams, [scene.gt_images[i] for i in views], depths, regions, most=300_000).colors


def lifted(select) -> np.ndarray:
    """3D points of the pixels `select(view)` picks (bool mask per view), from depth/."""
    out = []
    for i in views:
        ys, xs = np.nonzero(select(i) & np.isfinite(scene.depths[i]))
        out.append(backproject(scene.cameras[i], xs + 0.5, ys + 0.5, scene.depths[i][ys, xs]))
    return np.concatenate(out)


rng = np.random.default_rng(0)
obj = lifted(lambda i: scene.masks[i] == tid)
obj = obj[rng.choice(len(obj), min(len(obj), 20000), replace=False)]
up = mean_up(np.stack([c.R for c in scene.cameras]))
pts = samples.points
n = len(pts)
remaining = {"means": torch.as_tensor(pts, dtype=torch.float32), "quats": torch.tensor([[1.0, 0, 0, 0]]).repeat(n, 1),
             "scales": torch.full((n, 3), math.log(0.003)), "opacities": torch.full((n,), 3.0),
             "sh0": torch.zeros(n, 1, 3), "shN": torch.zeros(n, 15, 3), "identity": torch.zeros(n, 16)}
# which samples show another object (the cup, box, apple, sharpener): their masks through the same lifting
labels = [np.repeat(((scene.masks[i] != tid) & (scene.masks[i] != 0))[..., None], 3, axis=2) * 255.0 for i in views]
is_theirs = Samples.from_views(cams, labels, depths, regions, most=300_000).colors[:, 0] > 0.5
config = EffectsConfig()
plane = object_support(pts, obj, up)
search = find_shadow(remaining, obj, plane, samples, config)
shadow = search.shadow
assert shadow is not None, search.verdict
site = Site.of(obj, plane)
light = site.frame.light(shadow.elevation, shadow.azimuth)
print(f"{n} samples; shadow: {shadow.report()}")
# the support in the other objects' own cast shadows, as remove finds it (from their samples)
in_theirs, _ = their_shadows(site, light, pts, is_theirs, pts)


def db(a: np.ndarray, b: np.ndarray) -> float:
    return round(float(10 * np.log10(1.0 / max(float(((a - b) ** 2).mean()), 1e-12))), 2)


def report(name: str, colors: np.ndarray, changed: np.ndarray) -> None:
    if not changed.any():
        print(f"{name:38s} changed no samples")
        return
    ratio = np.percentile((colors[changed] + 1e-3) / (truth[changed] + 1e-3), [25, 50, 75], axis=0).round(3)
    print(f"{name:38s} changed samples {int(changed.sum()):6d}: {db(colors[changed], truth[changed])} dB "
          f"(input {db(samples.colors[changed], truth[changed])}), relit/gt {ratio.tolist()}", flush=True)


def cast_relit(spare_theirs: bool) -> tuple[np.ndarray, np.ndarray]:
    keep = shadow.shadowed & ~in_theirs if spare_theirs else shadow.shadowed
    gains = 1.0 + shadow.darkness[keep[shadow.shadowed]][:, None] * (shadow.gain[None] - 1.0)
    colors = samples.colors.copy()
    colors[keep] *= gains
    return colors, keep


def contact_relit(colors: np.ndarray, window: int = 2, grey: bool = False, spare_theirs: bool = False):
    contact = find_contact_shade(remaining, obj, plane, Samples(pts, colors), config, window=window,
                                 others=is_theirs)
    out, shaded = colors.copy(), np.zeros(n, bool)
    if contact is not None:
        gains, shaded = contact.gains, contact.shaded.copy()
        if grey:
            gains = np.repeat(np.exp(np.log(gains) @ LUMA / LUMA.sum())[:, None], 3, axis=1)
        if spare_theirs:
            stay = ~in_theirs[shaded]
            shaded[shaded] = stay
            gains = gains[stay]
        out[shaded] *= gains
    return out, shaded


for spare in (False, True):
    relit, cast = cast_relit(spare)
    tag = "their shadows kept, " if spare else ""
    report(f"{tag}cast shadow only", relit, cast)
    for name, kw in (("contact as today", {}), ("contact grey", dict(grey=True)),
                     ("contact window 9", dict(window=4)), ("contact window 13", dict(window=6))):
        if spare and name not in ("contact as today", "contact grey"):
            continue
        final, shaded = contact_relit(relit, spare_theirs=spare, **kw)
        report(f"{tag}{name}", final, cast | shaded)
        report(f"{tag}{name}, its own zone", final, shaded)
