"""The benchmark's failure table and speed-against-accuracy chart, from result records as the benchmark writes
them (no scene is trained: the records are what is under test)."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))

from benchmark_report import HEIGHT, speed_accuracy_chart, stability_lines  # noqa: E402


def cell(scene: str, method: str, m_psnr: float | None, status: str = "done", reason: str = "") -> dict:
    return {"scene": scene, "seed": 0, "method": method, "status": status, "reason": reason, "psnr": 30.0,
            "m_psnr": m_psnr, "seconds": 100.0, "removed_scores": {"psnr": 29.0, "m_psnr": 18.0}}


CELLS = [cell("a", "Init-telea", 19.0), cell("a", "FT-telea(3)[l1]", 17.5),
         cell("b", "Init-telea", None, "failed", "CUDA out of memory. Tried to allocate 2 GiB"),
         cell("b", "FT-telea(3)[l1]", None, "failed", "engine crashed | exit 1")]


def test_failure_table_names_crashes_out_of_memory_and_fills_worse_than_unfilled():
    text = "\n".join(stability_lines(CELLS))
    failures = text.split("## Failures")[1]
    assert "| a | 0 | FT-telea(3)[l1] | worse than unfilled | m-PSNR 17.50 against 18.00 dB |" in failures
    assert "| b | 0 | Init-telea | out of memory |" in failures
    assert "| b | 0 | FT-telea(3)[l1] | crash | engine crashed / exit 1 |" in failures  # a | would split the row
    assert "Init-telea | worse" not in failures  # 19.0 dB is above the unfilled 18.0


def test_chart_has_a_row_per_scene_a_mean_row_and_numbered_methods():
    chart = speed_accuracy_chart([*CELLS, cell("b", "Init-telea", 20.0)])
    titles = [item[3] for item in chart["items"] if item[0] == "text" and "(dB)" in str(item[3])]
    assert titles == ["a: m-PSNR (dB)", "a: PSNR (dB)", "b: m-PSNR (dB)", "b: PSNR (dB)",
                      "mean over scenes: m-PSNR (dB)", "mean over scenes: PSNR (dB)"]
    legend = [item[3] for item in chart["items"] if item[0] == "text" and "  " in str(item[3])]
    assert legend == ["1  FT-telea(3)[l1]", "2  Init-telea"]
    assert chart["height"] > 3 * HEIGHT
    unfilled = [item for item in chart["items"] if item[0] == "text" and item[3] == "unfilled"]
    assert len(unfilled) == 6  # the unfilled scene's line in every panel
