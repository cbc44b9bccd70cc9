"""The shape of the code: import rules, one place for each layout, plug-ins found by the CLI and the benchmark."""

from __future__ import annotations

import ast
import csv
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def test_import_rules_hold():
    """pyproject.toml's import-linter contracts: stages import only lower stages, the engine never imports
    Blender, Blender-side code never imports torch and reaches the engine only through engine.formats."""
    proc = subprocess.run([str(Path(sys.executable).parent / "lint-imports")], cwd=REPO, capture_output=True,
                          text=True)
    assert proc.returncode == 0, proc.stdout[-3000:]
    assert "0 broken" in proc.stdout


def _joined_names(path: Path) -> set[str]:
    """The string constants joined onto a path with `/` in a source file (`root / "removed"`)."""
    return {n.right.value for n in ast.walk(ast.parse(path.read_text())) if isinstance(n, ast.BinOp)
            and isinstance(n.op, ast.Div) and isinstance(n.right, ast.Constant) and isinstance(n.right.value, str)}


# the files and folders of a scene or run folder; engine/formats/layout.py alone joins them onto a path
LAYOUT_NAMES = {"point_cloud.ply", "classifier.npz", "removal.json", "holes.json", "scores.json", "split.json",
                "objects.json", "metrics.json", "config.json", "scene.json", "gt_depth", "inpainted", "removed",
                "checkpoints", "sparse", "images", "depth", "masks", "gt", "holes", "unseen", "renders", "complete"}


# the same words for folders that are not ours: torch hub's weights, pycolmap's scratch reconstruction
NOT_OURS = {("engine/base/weight_files.py", "checkpoints"), ("benchmarks/metrics_agreement.py", "checkpoints"),
            ("engine/complete/recolmap.py", "sparse"), ("engine/capture/run.py", "sparse"),
            ("engine/capture/run.py", "images")}


def test_only_the_layout_module_spells_run_and_scene_file_names():
    folders = ("engine", "addon", "operators", "scripts", "benchmarks")
    sources = [p for folder in folders for p in (REPO / folder).rglob("*.py")]
    offenders = {}
    for path in sources:
        if path == REPO / "engine" / "formats" / "layout.py":
            continue
        name = str(path.relative_to(REPO))
        found = {n for n in _joined_names(path) & LAYOUT_NAMES if (name, n) not in NOT_OURS}
        if found:
            offenders[name] = sorted(found)
    assert not offenders, f"ask engine.formats.layout instead: {offenders}"


PLUGIN = '''
from engine.complete.registry import CompletionMethod, Option, register


@register
class Throwaway(CompletionMethod):
    name = "throwaway"
    label = "Throwaway"
    summary = "a method that exists only in this test"
    options = (Option("throw_far", 2, "how far"),)
    cells = {"throwaway2": {"throw_far": 2}}
'''


def test_a_method_in_one_new_file_reaches_the_cli_and_the_benchmark(tmp_path: Path):
    (tmp_path / "throwaway.py").write_text(PLUGIN)
    env = {**os.environ, "SPLATFILL_PLUGINS": str(tmp_path / "throwaway.py"), "PYTHONPATH": str(REPO)}
    help_text = subprocess.run([sys.executable, "-m", "engine", "complete", "--help"], cwd=REPO, env=env,
                               capture_output=True, text=True, check=True).stdout
    assert "throwaway" in help_text and "--throw-far" in help_text
    cells = subprocess.run([sys.executable, str(REPO / "scripts" / "benchmark.py"), "--list-methods"], cwd=REPO,
                           env=env, capture_output=True, text=True, check=True).stdout.split()
    assert "throwaway2" in cells and "ft3" in cells
    plain = subprocess.run([sys.executable, "-m", "engine", "complete", "--help"], cwd=REPO, capture_output=True,
                           text=True, check=True).stdout
    assert "throwaway" not in plain


def test_an_option_of_another_method_is_refused_not_ignored():
    from engine.base.errors import InputError
    from engine.complete.registry import get, resolve_options

    assert resolve_options(get("ft"), {"refs": 0, "recolmap": False}) == {"refs": 0, "perceptual": "st-lpips"}
    with pytest.raises(InputError, match="--recolmap is not an option of --method ft"):
        resolve_options(get("ft"), {"recolmap": True})


def test_the_readme_table_is_the_registry():
    proc = subprocess.run([sys.executable, "-m", "engine", "plugins", "--markdown"], cwd=REPO, capture_output=True,
                          text=True, check=True)
    assert proc.stdout.strip() in (REPO / "README.md").read_text(), \
        "README's plug-in table is stale: paste `python -m engine plugins --markdown` into it"


def test_make_demo_completes_only_from_views_it_inpainted():
    """`make demo`, the README's main job, runs each `complete` on an inpainter an `inpaint` before it wrote (no
    --inpainter: the default). Why: its FT step asked for telea's views after the default fill became coherence,
    and the main job stopped with "inpainted/telea missing" on a fresh machine."""
    from engine.base.defaults import DEFAULT_INPAINTER

    recipe = re.search(r"^demo:.*?\n((?:\t.*\n)+)", (REPO / "Makefile").read_text(), re.M)
    assert recipe, "Makefile has no demo recipe"
    written: set[str] = set()
    for line in recipe.group(1).splitlines():
        stage = re.search(r"-m engine (inpaint|complete)\b", line)
        if stage:
            named = re.search(r"--inpainter (\S+)", line)
            inpainter = named.group(1) if named else DEFAULT_INPAINTER
            if stage.group(1) == "inpaint":
                written.add(inpainter)
            else:
                assert inpainter in written, f"make demo completes from {inpainter}'s views, which it never inpaints"


DOCS = REPO / "docs"
RECORD_SUFFIXES = {".json", ".csv", ".md", ".txt", ".png", ".jpg"}


@pytest.mark.fast
def test_docs_hold_one_reference_and_only_the_records_it_quotes():
    """BENCHMARKS.md is a short reference, docs/ holds records (no scripts, patches, logs, archives, videos), and
    every results folder says where each of its files came from."""
    files = [p for p in DOCS.rglob("*") if p.is_file()]
    assert len(files) <= 150, f"{len(files)} files under docs/"
    assert not [p for p in files if p.suffix not in RECORD_SUFFIXES], "only records and pictures under docs/"
    assert len((DOCS / "BENCHMARKS.md").read_text().splitlines()) <= 300
    for folder in (p for p in (DOCS / "results").iterdir() if p.is_dir()):
        named = set(json.loads((folder / "provenance.json").read_text())) if folder.name != "decisions" else \
            {n for row in csv.DictReader((folder / "decisions.csv").open()) for n in row["records"].split()}
        unnamed = {p.name for p in folder.iterdir()} - named - {"provenance.json", "decisions.csv", "README.md"}
        assert not unnamed, f"{folder.name}: no provenance for {sorted(unnamed)}"
    quoted = set(re.findall(r"`docs/results/([\w/.-]+)`", (DOCS / "BENCHMARKS.md").read_text()))
    missing = [q for q in quoted if not (DOCS / "results" / q.rstrip("/")).exists()]
    assert not missing, f"BENCHMARKS quotes records that are not there: {missing}"


@pytest.mark.fast
def test_readme_puts_blender_before_the_command_line_and_stays_short():
    text = (REPO / "README.md").read_text()
    assert len(text.splitlines()) <= 250
    assert text.index("## In Blender") < text.index("## Your own capture") < text.index("## The stages")


@pytest.mark.fast
def test_code_names_no_runs_and_no_paths_outside_the_repository():
    """Comments give the reason for a value and a stable BENCHMARKS section, not the order in which work happened."""
    run_names = re.compile(r"\b([Rr]uns? \d+|run\d+/|[Ss]ession \d+|[Ii]ssue \d+|\.\./shared/|docs/benchmarks?/"
                           r"|(Fifth|Sixth|Seventh|Eighth|Ninth|Tenth) trainings)")
    sources = [p for folder in ("engine", "addon", "operators") for p in (REPO / folder).rglob("*.py")]
    found = {str(p.relative_to(REPO)): m[0] for p in sources for m in [run_names.search(p.read_text())] if m}
    assert not found, found
    assert not [p.name for p in (REPO / "scripts").glob("*.py") if p.name.startswith(("bench_", "check_", "profile_"))]
