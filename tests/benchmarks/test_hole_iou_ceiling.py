"""The ceiling the hole IoU as inpainted can reach: exact masks, grown as `inpaint` grows them."""

import numpy as np

from benchmarks.hole_iou_ceiling import grown_scores


def test_an_exact_hole_grown_a_pixel_loses_what_its_border_adds():
    """Grown by one px (a disc of radius 1: the four neighbours) a 3x3 hole takes 12 more: IoU 9/21; a 20x20 one
    80 more: 400/480; ungrown both are 1."""
    small, large = np.zeros((40, 40), bool), np.zeros((40, 40), bool)
    small[5:8, 5:8] = True
    large[10:30, 10:30] = True
    assert grown_scores([small, large], 0)["mean"] == 1.0
    scores = grown_scores([small, large], 1)
    assert np.isclose(scores["worst"], 9 / 21) and np.isclose(scores["mean"], (9 / 21 + 400 / 480) / 2), scores
