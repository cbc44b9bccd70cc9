"""benchmarks/keep_sweep.py's choice of Z on the tuning runs."""

from __future__ import annotations

from benchmarks.keep_sweep import mean_of


def test_the_choice_takes_the_best_mean_and_never_a_z_with_a_failed_cell():
    table = {"a": {"0": {"m_psnr": 20.0}, "1": {"m_psnr": 22.0}, "2": {"m_psnr": 30.0}},
             "b": {"0": {"m_psnr": 24.0}, "1": {"m_psnr": 23.0}, "2": {"error": "complete: CUDA error"}}}
    assert mean_of(table, 0.0) == 22.0 and mean_of(table, 1.0) == 22.5
    assert mean_of(table, 2.0) == float("-inf")
    assert max([0.0, 1.0, 2.0], key=lambda z: mean_of(table, z)) == 1.0
