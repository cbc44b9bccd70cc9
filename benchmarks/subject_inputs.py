"""What `segment --auto` chose its subject from, saved small enough to carry home and study on a CPU.

    python benchmarks/subject_inputs.py RUN OUT.npz [--device cuda]

For a trained run, the inputs of engine.segment.saliency_votes.subject exactly as `segment --auto` computes them
(the Gaussians' centres, opacities and base colours, the salient votes, the supports' `free` and `near` and level
planes (`planes`, rows n_x n_y n_z d; their bands `level`, `plane_tol` wide), the frame's up and the proposals'
voxel), the proposals' ids and the subject it chose, in one compressed npz (about 6 MB for 300,000 Gaussians; the
run's PLY is 90). Why: the subject a real capture gets changes from one training to the next (the statue's figure
alone at 709b800, the boulder with the figure's legs at 5b804af), and the GPU run's folder does not come back, so a
different rule can only be judged on what it was chosen from.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks.records import run_study_args  # noqa: E402
from engine.base.device import pick_device  # noqa: E402
from engine.geometry.scene_geometry import camera_frame, find_supports  # noqa: E402
from engine.segment.proposals import propose  # noqa: E402
from engine.segment.run import SegmentConfig, subject_evidence, subject_level, subject_supports  # noqa: E402
from engine.segment.saliency_votes import subject  # noqa: E402
from engine.train.trained_run import load_run  # noqa: E402


def main() -> int:
    args = run_study_args(__doc__)
    config, run = SegmentConfig(run=args.run, auto=True), load_run(args.run)
    device = pick_device(args.device)
    means = run.gaussians["means"].numpy()
    opacity = torch.sigmoid(run.gaussians["opacities"]).numpy()
    frame = camera_frame(run.scene.cameras)
    supports = find_supports(means, opacity, frame, config)
    ids, stats = propose(means, opacity, frame, supports, config)
    votes, seen, colours, voxel = subject_evidence(run, frame, config, stats, device)
    solid = opacity >= config.solid
    supports = subject_supports(supports, means, solid, votes, frame, config)
    level = subject_level(means, supports, frame, config)
    chosen, why = subject(votes, means, colours, solid, supports.free, supports.near, frame.up, voxel,
                          config.min_vote, config.stack_gap, config.grow_vote, level)
    np.savez_compressed(args.out, means=means.astype(np.float32), opacity=opacity.astype(np.float16),
                        colours=colours.astype(np.float16), votes=votes.astype(np.float16),
                        seen=seen.astype(np.uint8), free=supports.free, near=supports.near, solid=solid, level=level,
                        up=np.asarray(frame.up, np.float64), voxel=np.float64(voxel), min_vote=config.min_vote,
                        ids=ids.astype(np.uint8), chosen=chosen,
                        planes=np.array([[*n, d] for n, d in supports.planes], np.float64).reshape(-1, 4),
                        plane_tol=np.float64(config.plane_tol * frame.radius))
    print(args.out, why, "chosen", int(chosen.sum()), "of", len(means))
    return 0


if __name__ == "__main__":
    sys.exit(main())
