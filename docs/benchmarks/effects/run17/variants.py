"""What keeps the GPU livingroom under 30 dB outside the hole (run 4: 29.51 / 29.52 on two seeds): the removal's
effects stage on a trained run, as `remove` does it, and with each of run 4's two suspects mended, each scored on
the test views against gt/ (overshoot.py's scoring: PSNR outside the true hole and in the true effect pixels, the
effect pixels' removed / gt/ ratio per channel, 25th / 50th / 75th percentile).

    PYTHONPATH=. python docs/benchmarks/effects/run17/variants.py RUN OBJECT [--device cuda] (ONLY=part of a name)

The suspects (docs/BENCHMARKS.md, "The full table, run 4"):
- The contact shade's gain is greenest (R, G, B at most 2.43 / 2.79 / 2.74; the true shadow's 1.52 / 1.49 / 1.41):
  its 5-cell window sees the wood's red and tan stripes in other shares than the reference beside the zone, so
  texture counts as missing light. Variants: one grey gain per cell (the luminance of the darkening, all
  channels alike), or the window widened to 9 and 13 cells.
- The cup's, cube's and orange's own shadows lay inside the snowman's and were relit with it; gt/ keeps them.
  Variant: the support in another object's cast shadow, along the light the search found, left as it is (by both
  relights and by the contact shade), and its samples left out of what the second relight measures. This is what
  `remove` does since run 17 (engine.edit.effects.their_shadows), after the tiny CPU livingroom (+0.12 dB outside
  the hole) and the 640 scene's exact data (emulate_contact.py); "as before run 17" is the code of run 4. Here the
  search runs without the other objects and the variant takes them out as the engine does.
"""

import dataclasses
import os
import sys
from pathlib import Path

import numpy as np
import torch

from engine.edit import removal
from engine.edit.contact_shade import find_contact_shade
from engine.edit.effects import LUMA, Shadow, brighten, relight, residual_gain, their_shadows
from engine.edit.plane_grid import Site
from engine.edit.underside import find_underside, paint

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scoring import effects_stage, score  # noqa: E402

st = effects_stage(__doc__)
run, scene, device, remaining, core, plane = st.run, st.scene, st.device, st.remaining, st.core, st.plane
regions, others, after, config, before, search = st.regions, st.others, st.after, st.config, st.before, st.search
shadow = search.shadow
site = Site.of(core, plane)
light = site.frame.light(shadow.elevation, shadow.azimuth)
means = remaining["means"].numpy()
# the support (not the other objects themselves: their sides facing the light are lit in gt/) in their cast
# shadows, and the samples there, as remove finds them since run 17
in_theirs, samples_in_theirs = their_shadows(site, light, means, others, before.points[shadow.pick])
print(f"light {shadow.elevation:.1f} / {shadow.azimuth:.1f} deg; other objects' Gaussians {int(others.sum())}; "
      f"shadowed support in their cast {int((shadow.shadowed & in_theirs).sum())} of {int(shadow.shadowed.sum())}; "
      f"dark samples in it {int((shadow.dark & samples_in_theirs).sum())} of {int(shadow.dark.sum())}")


def keep_theirs(found: Shadow) -> Shadow:
    """The shadow without the support in the other objects' own cast shadows, nor their samples among the dark."""
    stay = found.shadowed & ~in_theirs
    darkness = found.darkness[stay[found.shadowed]]
    return dataclasses.replace(found, shadowed=stay, darkness=darkness, dark=found.dark & ~samples_in_theirs)


def shadow_relit(found: Shadow):
    """Both relights of the cast shadow, as removal._undo_effects does them."""
    first = relight(remaining, found)
    pictures = removal._rerendered(run, first, after, device)
    residual = residual_gain(found, before, removal._train_samples(scene, pictures, regions))
    return relight(first, dataclasses.replace(found, gain=residual)), residual


def darkening_undone(gaussians, window: int = 2, grey: bool = False, spare_theirs: bool = False):
    """The contact shade and the underside repaint, as removal.undo_darkening does them, with the variants."""
    pictures = removal._rerendered(run, gaussians, after, device)
    shown = removal._train_samples(scene, pictures, [np.zeros_like(region) for region in regions])
    contact = find_contact_shade(gaussians, core, plane, shown, config, window=window, others=others)
    if contact is not None:
        gains = contact.gains
        if grey:
            gains = np.repeat(np.exp(np.log(gains) @ LUMA / LUMA.sum())[:, None], 3, axis=1)
        shaded = contact.shaded
        if spare_theirs:
            stay = ~in_theirs[shaded]
            shaded = shaded.copy()
            shaded[shaded] = stay
            gains = gains[stay]
        gaussians = brighten(gaussians, shaded, gains)
        print(f"  contact gains at most {gains.max(0).round(3).tolist() if len(gains) else None}, "
              f"median {np.median(gains, 0).round(3).tolist() if len(gains) else None}")
    underside = find_underside(gaussians, core, plane, config, others)
    if underside is not None:
        gaussians = paint(gaussians, underside)
        print(f"  underside colour {underside.colour.round(3).tolist()}")
    return gaussians


variants = {
    "as before run 17": dict(theirs=False),
    "contact grey": dict(theirs=False, grey=True),
    "contact window 9": dict(theirs=False, window=4),
    "contact window 13": dict(theirs=False, window=6),
    "their shadows kept (remove since run 17)": dict(theirs=True),
    "their shadows kept, contact grey": dict(theirs=True, grey=True),
}
if os.environ.get("ONLY"):  # the variants to score, by a part of their name
    variants = {k: v for k, v in variants.items() if os.environ["ONLY"] in k}
relit = {}
for name, v in variants.items():
    with torch.no_grad():
        theirs = v.pop("theirs")
        if theirs not in relit:
            relit[theirs] = shadow_relit(keep_theirs(shadow) if theirs else shadow)
        gaussians, residual = relit[theirs]
        print(f"{name}: residual gain {residual.round(3).tolist()}")
        score(run, darkening_undone(gaussians, spare_theirs=theirs, **v), name, device)
