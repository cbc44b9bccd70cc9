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

import sys
from pathlib import Path

import numpy as np

from engine.edit.contact_shade import find_contact_shade
from engine.edit.effects import LUMA, EffectsConfig, Samples, find_shadow, their_shadows
from engine.edit.plane_grid import Site
from engine.edit.support_plane import object_support

sys.path.insert(0, str(Path(__file__).resolve().parent))
from exact_data import db, exact_data  # noqa: E402

ex = exact_data(sys.argv[1])
samples, truth, obj, pts, n = ex.samples, ex.truth, ex.obj, ex.pts, ex.n
remaining, is_theirs = ex.remaining, ex.is_theirs
config = EffectsConfig()
plane = object_support(pts, obj, ex.up)
search = find_shadow(remaining, obj, plane, samples, config)
shadow = search.shadow
assert shadow is not None, search.verdict
site = Site.of(obj, plane)
light = site.frame.light(shadow.elevation, shadow.azimuth)
print(f"{n} samples; shadow: {shadow.report()}")
# the support in the other objects' own cast shadows, as remove finds it (from their samples)
in_theirs, _ = their_shadows(site, light, pts, is_theirs, pts)


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
