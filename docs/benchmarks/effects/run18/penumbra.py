"""Run 5's livingroom missed the tip and the rim of the snowman's shadow (recall 0.65-0.68): is it the penumbra?
On the 640 scenes' exact data (run17/exact_data.py), the engine's shadow search with the cast footprint grown by
`cast_margin` cells (1: as `remove` does it; above 1 the samples cast into the grown footprint count as dark where
darker, engine.edit.effects.EffectsConfig), the other objects given as `remove` gives them. The support samples
are relit by the first relight (darkness x gain) and scored against gt/: PSNR over the true effect's samples
(the pixels where images/ and gt/ differ, lifted alike) and over all samples, and the shadowed samples' recall and
precision against the true effect.

    PYTHONPATH=. python docs/benchmarks/effects/run18/penumbra.py .bench/640/livingroom_s0 [MARGIN...]
"""

import sys
from pathlib import Path

from engine.edit.effects import EffectsConfig, find_shadow
from engine.edit.support_plane import object_support

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "run17"))
from exact_data import db, exact_data  # noqa: E402

ex = exact_data(sys.argv[1])
margins = [int(m) for m in sys.argv[2:]] or [1, 2, 3, 4, 6]
effect = ex.flags(lambda i: ex.scene.effects[i])
plane = object_support(ex.pts, ex.obj, ex.up)
colors, truth = ex.samples.colors, ex.truth
print(f"{ex.n} samples, {int(effect.sum())} in the true effect; as input: effect {db(colors[effect], truth[effect])} "
      f"dB, all {db(colors, truth)} dB")
for margin in margins:
    search = find_shadow(ex.remaining, ex.obj, plane, ex.samples, EffectsConfig(cast_margin=margin),
                         others=ex.is_theirs)
    shadow = search.shadow
    if shadow is None:
        print(f"margin {margin}: no shadow ({search.verdict})")
        continue
    relit = colors.copy()
    relit[shadow.shadowed] *= 1.0 + shadow.darkness[:, None] * (shadow.gain[None] - 1.0)
    hit = shadow.shadowed & effect
    print(f"margin {margin}: light {shadow.elevation:.1f} / {shadow.azimuth:.1f} deg, gain {shadow.gain.round(3)}; "
          f"shadowed {int(shadow.shadowed.sum())}, recall {hit.sum() / effect.sum():.3f}, precision "
          f"{hit.sum() / max(shadow.shadowed.sum(), 1):.3f}; effect {db(relit[effect], truth[effect])} dB, "
          f"all {db(relit, truth)} dB", flush=True)
