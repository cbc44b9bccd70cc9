"""A `segment --auto` subject rule judged on a run's carried inputs against a generated scene's truth, on a CPU.

    PYTHONPATH=. python benchmarks/subject_sweep.py INPUTS.npz SCENE [--grow-votes 0.5 0.3 0.2 ...]

INPUTS.npz is benchmarks/subject_inputs.py's (gpu.sh subject-inputs, or by hand on a GPU run); SCENE the generated
scene the run trained on. Each Gaussian's truth is the object most of the views that see it show there (its centre
within 2% of the view's true depth, in 3 views at least); a subject's hidden interior is in no view, so it counts
against every rule alike: compare rows, not scenes. Why: a run's per-Gaussian identity is rewritten by `segment`,
and the GPU run's folder does not come back, so a rule (here the growth's vote, GROW_VOTE) can only be judged on
what the subject was chosen from.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from engine.capture.scene import load_scene  # noqa: E402
from engine.edit.holes import iou  # noqa: E402
from engine.formats.cameras import project, sample_nearest  # noqa: E402
from engine.segment.saliency_votes import subject  # noqa: E402

SEEN_TOL, MIN_VIEWS = 0.02, 3


def truth_by_object(scene_dir: str, means: np.ndarray) -> tuple[dict[str, np.ndarray], str]:
    """Per object name, (N,) bool: the Gaussians most views that see them show as that object; and the target's name."""
    scene = load_scene(scene_dir, depth=True)
    if scene.masks is None or scene.depths is None or scene.target is None:
        raise SystemExit(f"{scene_dir}: needs masks/ with a target and depth/ (a generated scene)")
    seen, shown = np.zeros(len(means)), {o.id: np.zeros(len(means)) for o in scene.objects}
    for camera, mask, depth in zip(scene.cameras, scene.masks, scene.depths, strict=True):
        u, v, z = project(camera, means)
        surface, inside = sample_nearest(depth, u, v)
        ids, _ = sample_nearest(mask, u, v)
        visible = inside & (z > 0) & (np.abs(z - surface) < SEEN_TOL * np.abs(z))
        seen += visible
        for object_id, count in shown.items():
            count += visible & (ids == object_id)
    return ({o.name: (seen >= MIN_VIEWS) & (shown[o.id] > 0.5 * np.maximum(seen, 1)) for o in scene.objects},
            scene.target.name)


def main(args: list[str]) -> None:
    grow_votes = [float(a) for a in args[args.index("--grow-votes") + 1:]] if "--grow-votes" in args else [0.5, 0.2]
    inputs = np.load(args[0])
    means = inputs["means"].astype(np.float64)
    truths, target = truth_by_object(args[1], means)
    print(f"{args[0]}: voxel {float(inputs['voxel']):.4f}, {len(means)} Gaussians, truth "
          + ", ".join(f"{k} {int(t.sum())}" for k, t in truths.items()))
    for grow_vote in grow_votes:
        chosen, _ = subject(inputs["votes"].astype(np.float64), means, inputs["colours"].astype(np.float64),
                            inputs["solid"], inputs["free"], inputs["near"], inputs["up"], float(inputs["voxel"]),
                            float(inputs["min_vote"]), grow_vote=grow_vote,
                            level=inputs["level"] if "level" in inputs.files else None)
        others = ", ".join(f"{k} {(chosen & t).sum() / max(t.sum(), 1):.3f}" for k, t in truths.items() if k != target)
        print(f"grow over {grow_vote:.2f}: chosen {int(chosen.sum())}, {target} IoU {iou(chosen, truths[target]):.3f};"
              f" share of the others taken: {others or 'none'}")


if __name__ == "__main__":
    main(sys.argv[1:])
