"""engine.complete.scoring.kept_changes: where a completion changed a view outside its hole, told apart as a small
change everywhere (a blur) or a large one beside the hole (a spill) or far from it."""

from __future__ import annotations

import numpy as np

from engine.complete.scoring import CHANGED_LEVELS, kept_changes


def _view() -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    before = rng.integers(40, 200, (96, 128, 3)).astype(np.uint8)
    hole = np.zeros((96, 128), bool)
    hole[40:56, 56:72] = True
    return before, ~hole


def test_a_small_change_everywhere_is_not_counted_as_changed_pixels():
    before, outside = _view()
    after = before + np.uint8(CHANGED_LEVELS // 2)
    found = kept_changes(after, before, outside)
    assert found["changed_share"] == 0 and found["changed_near_hole"] == 0
    assert abs(found["psnr"] - 20 * np.log10(255 / (CHANGED_LEVELS // 2))) < 0.01


def test_a_spill_beside_the_hole_and_a_change_far_from_it_are_told_apart():
    before, outside = _view()
    spill, far = before.copy(), before.copy()
    spill[36:40, 56:72] += 60  # a band of 4 px along the hole's top edge
    far[0:4, 0:16] += 60  # the same count of pixels in a corner, far past NEAR_HOLE_PX
    near, away = kept_changes(spill, before, outside), kept_changes(far, before, outside)
    assert near["changed_share"] == away["changed_share"] == round(64 / outside.sum(), 5)
    assert near["changed_near_hole"] == 1.0 and away["changed_near_hole"] == 0.0
    assert kept_changes(before, before, outside)["psnr"] is None  # nothing changed: no finite PSNR to report
