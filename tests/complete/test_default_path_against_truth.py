"""What the default path promises, checked against the truth on a tiny scene of its own (a scene seed no other test
uses, ground truth on every view): the removal leaves the rest of every view as the truth shows it, the hole masks
as inpainted overlap the true holes, `complete` at its defaults asks for the default inpainting first, in one line,
and then fills the hole with the method the tuning scenes chose (engine.base.defaults), which keeps the hole at
least as good as the removal left it.

Why not 'above the unfilled hole' (this test's bar until ba1253c): since `remove` colours the patch it lays from
what the training views render of the ring around the object (EffectsConfig.seen_colour), the unfilled hole here
scores 31.4-33.3 dB (28.6-31.2 before; seed 0 within 1.3 dB of the truth's own blur, benchmarks/hole_error.py's blur
oracle): this scene's true holes are a few tens of pixels a view, and the fill has next to nothing left to win.
Whether the default fill beats the unfilled hole by the issue's 1.5 dB is the held-out table's question (GPU,
docs/BENCHMARKS.md).

The thresholds come from the spread measured over training seeds 0, 1 and 2 (MEASURED below); the test runs
seed 0. Measure them again with `.venv/bin/python tests/complete/test_default_path_against_truth.py 0 1 2`, which
prints one line a seed to stderr (the stages' threads redirect standard output while C libraries write).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

# livingroom at scene seed 11, 16 views and 6 extra test views of 96 px, truth on every view
SCENE = ["--views", "16", "--res", "96", "--samples", "4", "--seed", "11", "--points", "3000", "--gt", "all",
         "--extra-test", "6"]
# training seed -> (the default fill's m-PSNR, unfilled m-PSNR, hole IoU as inpainted, removal's PSNR outside the true
# hole over every view), dB and IoU, on the 2-core CPU at ba1253c (Ref-coherence[warm], training only the hole; the
# holes take the band the photos contradict, 4 px here, and grow by 1 px before inpainting: at 96 px nearly all the
# band is off, so their IoU against the unseen truth is low; at e541ab4, the patch in its base colour: 31.71 / 29.67,
# 34.41 / 28.63, 33.71 / 31.15)
MEASURED: dict[int, tuple[float, float, float, float]] = {
    0: (32.60, 32.95, 0.070, 27.32), 1: (32.34, 31.42, 0.068, 27.17), 2: (33.27, 33.32, 0.067, 26.85)}
SPOIL = 1.0  # the default fill's m-PSNR below the unfilled hole's, less than (measured -0.35 to +0.91 dB; coherence
# turned to black in the masks: -5.46)
HOLE_IOU = 0.05  # mean IoU of the masks as inpainted against the true holes, at least (measured 0.067-0.070)
OUTSIDE = 25.0  # removal's PSNR outside the true hole, mean over every view, at least (measured 26.85-27.32 dB;
# with nothing removed, 20.72)


def default_path(scene: Path, work: Path, seed: int) -> dict:
    """train (the tiny preset), remove the scene's target, holes, `complete` at its defaults before any inpainting
    (refused), then `inpaint` and `complete` at their defaults."""
    from engine.base.errors import InputError
    from engine.complete.run import CompleteConfig, run_complete
    from engine.edit.holes import HoleConfig, run_holes
    from engine.edit.removal import RemovalConfig, run_removal
    from engine.inpaint.run import InpaintConfig, run_inpaint
    from engine.train.config import TrainConfig
    from engine.train.run import train

    run = work / f"run{seed}"
    train(TrainConfig(scene=str(scene), out=str(run), preset="tiny", device="cpu", steps=800, refine_start=50,
                      refine_stop=150, seed=seed))
    target = next(o["name"] for o in json.loads((scene / "masks" / "objects.json").read_text()) if o.get("target"))
    removal = run_removal(RemovalConfig(run=str(run), object=target, device="cpu"))
    run_holes(HoleConfig(run=str(run)))
    try:
        run_complete(CompleteConfig(run=str(run), device="cpu", turntable=False))
        unready = ""
    except InputError as exc:
        unready = str(exc)
    inpainted = run_inpaint(InpaintConfig(run=str(run)))
    report = run_complete(CompleteConfig(run=str(run), device="cpu", turntable=False))
    return {"completed": report["scores"]["m_psnr"], "unfilled": report["removed_scores"]["m_psnr"],
            "hole_iou": inpainted["hole_iou_as_inpainted"]["mean"],
            "outside": removal["psnr_outside_hole_every_view"]["mean"],
            "method": report["method"], "unready": unready}


@pytest.fixture(scope="module")
def measured(tmp_path_factory) -> dict:
    """Made once per test run (a worker may tear a module's fixtures down between its tests and set them up again)."""
    from tests.conftest import made_once, make_scene

    scene = made_once(tmp_path_factory, "scene-livingroom-s11", lambda out: make_scene(out, "livingroom", SCENE))

    def run(out: Path) -> None:
        out.mkdir(parents=True)
        numbers = default_path(scene, out, seed=0)
        (out / "measured.json").write_text(json.dumps(numbers))

    return json.loads((made_once(tmp_path_factory, "default-path-s11", run) / "measured.json").read_text())


pytestmark = pytest.mark.slow


def test_removal_leaves_the_rest_of_every_view_as_the_truth_shows_it(measured):
    assert measured["outside"] >= OUTSIDE, measured


def test_the_masks_as_inpainted_cover_the_true_holes(measured):
    assert measured["hole_iou"] >= HOLE_IOU, measured  # no masks at all: 0


def test_complete_at_its_defaults_asks_for_the_default_inpainting_first(measured):
    assert "engine inpaint --inpainter coherence" in measured["unready"], measured


def test_complete_at_its_defaults_fills_the_hole_with_the_method_the_tuning_scenes_chose(measured):
    assert measured["method"] == "Ref-coherence[warm]", measured  # the hole left: None


def test_the_default_fill_keeps_the_hole_at_least_as_good_as_the_removal_left_it(measured):
    assert measured["completed"] - measured["unfilled"] > -SPOIL, measured


if __name__ == "__main__":
    import tempfile

    sys.path.insert(0, str(REPO / "tests"))
    from conftest import make_scene

    root = Path(tempfile.mkdtemp(prefix="default-path-"))
    make_scene(root / "scene", "livingroom", SCENE)
    for training_seed in map(int, sys.argv[1:] or ["0"]):
        print(json.dumps({"seed": training_seed, **default_path(root / "scene", root, training_seed)}), file=sys.stderr,
              flush=True)
