"""How well Ref's carry reproduces the hole of other views, in 2D on the generator's exact data (CPU).

Ref trains on every training view's hole rewritten with one reference view's fill (`carry_fill`); what
training then sees in a view's hole is the carried fill. Here the test views of a generated scene stand in
for the training views: each view's hole is the exact hole (holes/), its "removed render" is gt/ with that
hole left to the inpainter, and its depth is gt_depth/ inpainted the same way, so the fills are the
inpainter's own and only the carry is measured. The reference is chosen by `reference_view` as in Ref; every
other view is scored in its hole against gt/: PSNR and SSIM (the benchmark's m-PSNR and m-SSIM) of its own
fill and of the carried fill.

    PYTHONPATH=.:docs/benchmarks/effects/run9 python carry_eval.py INPAINTER SCENE...
"""

import sys
import time
from pathlib import Path

import numpy as np
from exact_fills import hole_scores, own_fills

from engine.complete.reference_fill import carry_fill, reference_view
from engine.inpaint.registry import create

inpainter = create(sys.argv[1])
for path in map(Path, sys.argv[2:]):
    t0 = time.time()
    fills, truths = own_fills(inpainter, path)
    t1 = time.time()
    r = reference_view(fills)
    ref, own, carried, share = fills[r], [], [], []
    for i, view in fills.items():
        if i == r:
            continue
        out, count = carry_fill(view.camera, view.hole, view.depth, view.image, ref.camera, ref.hole, ref.depth,
                                ref.image)
        own.append(hole_scores(view.image, truths[i], view.hole))
        carried.append(hole_scores(out, truths[i], view.hole))
        share.append(int(np.sum(count)) / view.hole.sum())  # carry_fill returns the carried mask since run12
    own, carried = np.array(own).mean(0), np.array(carried).mean(0)
    print(f"{path.name} {sys.argv[1]}: reference {ref.camera.name} of {len(fills)} views; own fill m-PSNR "
          f"{own[0]:.2f} m-SSIM {own[1]:.3f}; carried {carried[0]:.2f} / {carried[1]:.3f} ({np.mean(share):.2f} "
          f"of the hole carried); inpainting {t1 - t0:.0f} s, reference and carry {time.time() - t1:.0f} s", flush=True)
