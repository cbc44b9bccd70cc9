"""Where the relit shadow's overshoot comes from (run 3: the GPU livingroom's shadow 5-20% brighter than gt/ after
removal, while on the scene's exact data the gain is within 1-3%, emulate_gain.py): the removal's effects stage
step by step on a trained run, with the second relight measured several ways, each scored on the test views
against gt/.

    PYTHONPATH=. python docs/benchmarks/effects/run16/overshoot.py RUN OBJECT [--device cuda] (ONLY=part of a name)

Prints, after the first relight: the shadow's dark samples against the lit ones beside it (all of them, beyond the
contact shade's zone, each part alone), how much the first relight brightened the dark samples against the gain.
Then per variant of the second relight (lit against dark, as before run 16; as today, engine.edit.effects.
residual_gain: what the dark samples fell short of the gain; none; beyond the zone; beyond the zone by trimmed
means; over the dark samples the first relight reached, everywhere and beyond the zone): PSNR outside the true
hole, in the true effect pixels, and the effect pixels' removed / gt/ ratio per channel (25th, 50th, 75th
percentile), each after the contact shade and the underside repaint as `remove` does them. Run 16 ran it with
the lit-against-dark residual as residual_gain and "short of the gain" as a variant (records/*/overshoot.txt).
"""

import dataclasses
import os
import sys
from pathlib import Path

import numpy as np
import torch

from engine.edit import removal
from engine.edit.effects import relight, residual_gain
from engine.edit.plane_grid import Site
from engine.io.masks import dilate

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "run17"))
from scoring import effects_stage, score  # noqa: E402  (shared with run17/variants.py)

st = effects_stage(__doc__)
run, scene, device, remaining, core, plane = st.run, st.scene, st.device, st.remaining, st.core, st.plane
regions, others, after, config, before, search = st.regions, st.others, st.after, st.config, st.before, st.search
shadow = search.shadow
first = relight(remaining, shadow)
after1 = removal._rerendered(run, first, after, device)
samples1 = removal._train_samples(scene, after1, regions)

# the contact shade's zone on the plane, for the samples the gain was measured on
site = Site.of(core, plane)
near_cells = dilate(site.grid.raster(site.frame.flat(core), site.spacing),
                    max(1, round(config.contact_reach * site.radius / site.grid.cell)))
picked = before.points[shadow.pick]
far = ~site.grid.cells(near_cells, site.frame.flat(picked))


def ratio(colors: np.ndarray, lit: np.ndarray, dark: np.ndarray, how: str = "median") -> np.ndarray:
    if lit.sum() < 20 or dark.sum() < 20:
        return np.ones(3)
    if how == "median":
        return (np.median(colors[lit], 0) + 1e-3) / (np.median(colors[dark], 0) + 1e-3)

    def trimmed(v: np.ndarray) -> np.ndarray:
        low, high = np.percentile(v, [10, 90], axis=0)
        keep = (v >= low) & (v <= high)
        return (v * keep).sum(0) / np.maximum(keep.sum(0), 1)
    return (trimmed(colors[lit]) + 1e-3) / (trimmed(colors[dark]) + 1e-3)


c0, c1 = before.colors[shadow.pick], samples1.colors[shadow.pick]
dark, lit = shadow.dark, shadow.lit
print(f"gain {shadow.gain.round(3)}; samples: dark {dark.sum()} ({(dark & far).sum()} beyond the contact zone), "
      f"lit {lit.sum()} ({(lit & far).sum()} beyond)")
print("residual, all dark against all lit (before run 16):", np.clip(ratio(c1, lit, dark), 1, 4).round(3))
print("residual, beyond the contact zone:", np.clip(ratio(c1, lit & far, dark & far), 1, 4).round(3))
print("residual, dark inside the zone against all lit:", ratio(c1, lit, dark & ~far).round(3))
print("residual, beyond, trimmed means:", ratio(c1, lit & far, dark & far, "trimmed").round(3))
bright = (c1[dark] + 1e-3) / (c0[dark] + 1e-3)
print("first relight brightened the dark samples by (25/50/75):",
      np.percentile(bright, [25, 50, 75], 0).round(3).tolist())
# the dark samples the first relight reached: brightened by at least a third of the gain (in log luminance). Those
# it left alone (the crater under the object, other objects' feet, what lies below the band) are no shadow the
# second relight could mend, and their dark median is what would make it overshoot.
LUM = np.array([0.2126, 0.7152, 0.0722])
reached = np.zeros_like(dark)
reached[dark] = np.log((c1[dark] @ LUM + 1e-3) / (c0[dark] @ LUM + 1e-3)) > np.log(shadow.gain @ LUM) / 3
print(f"dark samples the first relight reached: {(dark & reached).sum()} of {dark.sum()}; residual over them:",
      ratio(c1, lit, dark & reached).round(3),
      "beyond the zone too:", ratio(c1, lit & far, dark & reached & far).round(3))


def finish(gaussians):
    """The contact shade and the underside repaint after the shadow, as removal does them."""
    pictures = removal._rerendered(run, gaussians, after, device)
    return removal.undo_darkening(run, gaussians, core, plane, regions, pictures, device, others, config)[0]


variants = {
    "lit against dark (before run 16)": np.clip(ratio(c1, lit, dark), 1, 4),
    "second relight as today": residual_gain(shadow, before, samples1),
    "no second relight": np.ones(3),
    "second relight beyond the zone": np.clip(ratio(c1, lit & far, dark & far), 1, 4),
    "beyond the zone, trimmed means": np.clip(ratio(c1, lit & far, dark & far, "trimmed"), 1, 4),
    "over the dark samples it reached": np.clip(ratio(c1, lit, dark & reached), 1, 4),
    "reached, beyond the zone": np.clip(ratio(c1, lit & far, dark & reached & far), 1, 4),
}
if os.environ.get("ONLY"):  # the variants to score, by a part of their name
    variants = {k: v for k, v in variants.items() if os.environ["ONLY"] in k}
for name, residual in variants.items():
    with torch.no_grad():
        relit = finish(relight(first, dataclasses.replace(shadow, gain=residual)))
        score(run, relit, f"{name} {residual.round(3)}", device)
