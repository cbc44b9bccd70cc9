"""make_scene.py's arguments: a preset names the sizes, a flag given beside it wins."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.fast


def test_the_benchmark_preset_gives_its_sizes_and_a_flag_beside_it_wins():
    from scripts.make_scene import PRESETS, parse_args

    scene = parse_args(["--family", "statue", "--out", "x", "--preset", "benchmark"])
    assert {k: getattr(scene, k) for k in PRESETS["benchmark"]} == PRESETS["benchmark"]
    assert scene.gt == "all" and scene.extra_test >= 50  # truth on training views; set metrics need 50 a side
    assert parse_args(["--family", "statue", "--out", "x", "--preset", "benchmark", "--views", "12"]).views == 12
    assert parse_args(["--family", "statue", "--out", "x"]).views == 100  # no preset: the default sizes
