"""Splatted colours (Ref before 104a864) against colours read back along the splatted surface (today's
`carry_fill`), on the same fills: for the reference `reference_view` picks, the best one, and the mean over
every view as the reference (CPU, the generator's exact data; carry_eval.py says how the fills are made).
Needs the old module beside it:

    git show 43d00e9:engine/complete/reference_fill.py > DIR/old_reference_fill.py
    PYTHONPATH=.:DIR:docs/benchmarks/effects/run9 python carry_compare.py INPAINTER SCENE...
"""

import sys
from pathlib import Path

import numpy as np
import old_reference_fill as old
from exact_fills import hole_scores, own_fills

from engine.complete.reference_fill import ViewFill, carry_fill, reference_view
from engine.inpaint.registry import create

CARRIES = {"splat colours": old.carry_fill, "read back": carry_fill}


def carried_scores(carry, fills: dict[int, ViewFill], truths: dict[int, np.ndarray], r: int) -> np.ndarray:
    ref = fills[r]
    return np.array([hole_scores(carry(v.camera, v.hole, v.depth, v.image, ref.camera, ref.hole, ref.depth,
                                       ref.image)[0], truths[i], v.hole) for i, v in fills.items() if i != r]).mean(0)


inpainter = create(sys.argv[1])
for path in map(Path, sys.argv[2:]):
    fills, truths = own_fills(inpainter, path)
    own = np.array([hole_scores(f.image, truths[i], f.hole) for i, f in fills.items()]).mean(0)
    pick = reference_view(fills)
    for name, carry in CARRIES.items():
        every = {r: carried_scores(carry, fills, truths, r) for r in fills}
        mean, best = np.array(list(every.values())).mean(0), max(every.values(), key=lambda s: s[0])
        print(f"{path.name} {sys.argv[1]} {name}: own {own[0]:.2f}/{own[1]:.3f}; picked reference "
              f"{fills[pick].camera.name} {every[pick][0]:.2f}/{every[pick][1]:.3f}; best {best[0]:.2f}/{best[1]:.3f}; "
              f"mean over references {mean[0]:.2f}/{mean[1]:.3f}", flush=True)
