"""The benchmark's failure table and speed-against-accuracy chart, from result records as the benchmark writes
them (no scene is trained: the records are what is under test)."""

from __future__ import annotations

from pathlib import Path

from benchmarks.matrix_report import HEIGHT, speed_accuracy_chart, stability_lines


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


def test_run_time_is_end_to_end_and_each_cell_carries_its_share_of_the_shared_stages():
    """Two cells of one scene share a 100 s base run and removal; Direct paints the inputs (no holes) but waits
    for them too: end to end it is 100 + 20 + 30 + 10 s, its share 60 + 30 + 10 (the others split holes)."""
    from benchmarks.matrix import add_shares

    base = {"train": 100.0, "remove": 20.0}
    init = cell("a", "Init-telea", 19.0) | {"stages": base | {"holes": 6.0, "inpaint-telea": 8.0},
                                             "complete_seconds": 50.0}
    direct = cell("a", "Direct-telea", 18.0) | {"stages": base | {"inpaint-direct-telea": 30.0},
                                                 "complete_seconds": 10.0}
    shared = add_shares([init, direct])
    assert shared[1]["share_seconds"] == 50 + 10 + 30 + 10 and shared[0]["share_seconds"] == 60 + 6 + 8 + 50


def test_set_metrics_are_not_averaged_across_scenes_and_a_negative_kid_ties_with_zero():
    from benchmarks.matrix import _table, summarise

    cells = [cell(s, m, 19.0) | {"fid": f, "kid": k} for s, m, f, k in
             (("a", "Init-telea", 40.0, -0.01), ("a", "Ref-telea", 50.0, 0.0), ("b", "Init-telea", 30.0, 0.02))]
    summary = summarise(cells)
    assert summary["all"]["Init-telea"].get("fid") is None and summary["a"]["Init-telea"]["fid"] == 40.0
    rows = {line.split(" | ")[0]: line for line in _table(summary["a"])}
    assert "**-0.0100**" in rows["| Init-telea"] and "**0.0000**" in rows["| Ref-telea"]  # a tie at zero


def test_cells_of_two_commits_are_refused_in_one_table_unless_asked_and_then_named_by_commit(tmp_path: Path):
    import json

    import pytest

    from benchmarks.matrix import MixedCommits, write_results

    cells = [cell("a", "Init-telea", 19.0) | {"commit": "abc1234"},
             cell("a", "Ref-telea", 20.0) | {"commit": "def5678"}]
    with pytest.raises(MixedCommits, match="2 commits"):
        write_results(cells, tmp_path)
    assert len(json.loads((tmp_path / "results.json").read_text())) == 2  # the records are kept all the same
    write_results(cells, tmp_path, mixed=True)
    text = (tmp_path / "tables.md").read_text()
    assert "| Init-telea @abc1234 |" in text and "| Ref-telea @def5678 |" in text


def test_held_out_and_tuning_scenes_are_averaged_apart_and_a_tuning_tool_refuses_a_held_out_scene(tmp_path: Path):
    import json

    import pytest

    from benchmarks.matrix import summarise
    from engine.base.errors import InputError
    from engine.formats.protocol import refuse_held_out, scene_role

    for name, seed in (("held", 117), ("tuned", 3)):
        (tmp_path / name).mkdir()
        (tmp_path / name / "scene.json").write_text(json.dumps({"generator": "scripts/make_scene.py", "seed": seed}))
    assert scene_role(tmp_path / "held") == "held-out" and scene_role(tmp_path / "tuned") == "tuning"
    assert scene_role(tmp_path) is None  # a capture: no generator seed
    with pytest.raises(InputError, match="held-out scene"):
        refuse_held_out(tmp_path / "held", "removal_sweep.py")
    refuse_held_out(tmp_path / "tuned", "removal_sweep.py")
    cells = [cell("a", "Init-telea", 19.0) | {"role": "held-out"}, cell("b", "Init-telea", 25.0) | {"role": "tuning"}]
    summary = summarise(cells)
    assert summary["all held-out"]["Init-telea"]["m_psnr"] == 19.0 and "all" not in summary


def test_a_scene_table_gives_the_hole_masks_as_written_and_as_inpainted_and_the_removal_with_worst_views(
        tmp_path: Path):
    from benchmarks.matrix import write_results

    scores = {"hole_iou": 0.54, "unseen_iou": 0.93, "hole_iou_inpainted": 0.5, "hole_iou_inpainted_worst": 0.2,
              "removal_psnr_outside": 31.0, "removal_psnr_outside_worst": 27.5}
    write_results([cell("a", "Init-telea", 19.0) | scores], tmp_path)
    table = (tmp_path / "tables.md").read_text()
    assert "0.540 as written, 0.500 as inpainted (worst view 0.200), 0.930 for their unseen part alone" in table
    assert "PSNR outside the true hole: 31.00 dB (worst view 27.50)" in table


def test_the_oracles_stand_beside_the_methods_unranked():
    from benchmarks.matrix import _table, summarise

    oracle = {"flat": {"m_psnr": 24.0}, "blur": {"m_psnr": 30.0}}
    rows = summarise([cell("a", "Init-telea", 19.0) | {"oracle_scores": oracle}])["a"]
    assert rows["Oracle: truth blurred 4 px"]["m_psnr"] == 30.0
    lines = {line.split(" | ")[0]: line for line in _table(rows)}
    assert "**30.00**" not in lines["| Oracle: truth blurred 4 px"] and "**19.00**" in lines["| Init-telea"]


def test_records_pictures_come_back_as_jpegs_no_wider_than_the_limit(tmp_path: Path):
    """gpu.sh collect's shrink: a wide PNG sheet becomes a JPEG of the same proportions at the width limit, a
    small one a JPEG of its own size; other records stay as they are."""
    import cv2
    import numpy as np

    from benchmarks.records import shrink_pictures

    (tmp_path / "heldout").mkdir()
    sheet = np.tile(np.linspace(0, 255, 2400, dtype=np.uint8)[None, :, None], (900, 1, 3))
    cv2.imwrite(str(tmp_path / "heldout" / "sheet.png"), sheet)
    cv2.imwrite(str(tmp_path / "small.png"), sheet[:40, :60])
    (tmp_path / "results.json").write_text("{}")
    assert shrink_pictures(tmp_path, width=1600) == 2
    assert sorted(p.name for p in tmp_path.rglob("*") if p.is_file()) == ["results.json", "sheet.jpg", "small.jpg"]
    assert cv2.imread(str(tmp_path / "heldout" / "sheet.jpg")).shape == (600, 1600, 3)
    assert cv2.imread(str(tmp_path / "small.jpg")).shape == (40, 60, 3)
