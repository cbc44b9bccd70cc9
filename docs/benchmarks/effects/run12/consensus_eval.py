"""Ref's consensus fill against its single fill and each view's own, in 2D on the generator's exact data (CPU).

As run9/carry_eval.py: the test views stand in for the training views, each with its exact hole inpainted in gt/
and gt_depth/ (the inpainter's own fills). The reference is `reference_view`'s; what each other view's hole would
train on is scored against gt/ there (m-PSNR, m-SSIM): its own fill, the reference's own fill carried, and the
consensus carried: the mean of every view's fill carried into the reference (the twelfth trainings' Ref) or
the median (`consensus_fill`, today's). Output: consensus_eval.txt.

    PYTHONPATH=. python consensus_eval.py INPAINTER SCENE...
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parents[1] / "run9"))
from exact_fills import hole_scores, own_fills  # noqa: E402

from engine.complete.reference_fill import ViewFill, carry_fill, consensus_fill, reference_view  # noqa: E402
from engine.inpaint.registry import create  # noqa: E402


def mean_fill(fills: dict[int, ViewFill], r: int) -> np.ndarray:
    """The first consensus (the twelfth trainings' Ref): the mean instead of the median."""
    ref = fills[r]
    stack = [np.where(ref.hole[..., None], ref.image, 0).astype(np.float32)]
    for i, view in fills.items():
        if i != r:
            out, carried = carry_fill(ref.camera, ref.hole, ref.depth, ref.image, view.camera, view.hole, view.depth,
                                      view.image)
            stack.append(np.where(carried[..., None], out, np.nan).astype(np.float32))
    image = ref.image.copy()
    image[ref.hole] = np.round(np.nanmean(np.stack(stack), axis=0)[ref.hole]).astype(image.dtype)
    return image


inpainter = create(sys.argv[1])
for path in map(Path, sys.argv[2:]):
    fills, truths = own_fills(inpainter, path)
    r = reference_view(fills)
    references = {"single": fills[r].image, "mean": mean_fill(fills, r), "median": consensus_fill(fills, r)}
    rows = {"own": [hole_scores(v.image, truths[i], v.hole) for i, v in fills.items() if i != r]}
    for name, image in references.items():
        ref = fills[r]
        rows[name] = [hole_scores(carry_fill(v.camera, v.hole, v.depth, v.image, ref.camera, ref.hole, ref.depth,
                                             image)[0], truths[i], v.hole) for i, v in fills.items() if i != r]
    print(f"{path.name} {sys.argv[1]} ({len(fills)} views, reference {fills[r].camera.name}): " + "; ".join(
        f"{k} {np.mean([s[0] for s in v]):.2f} / {np.mean([s[1] for s in v]):.3f}" for k, v in rows.items()),
        flush=True)
