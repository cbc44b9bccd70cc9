"""The command line's contract: every bad input is one line on stderr and status 2, never a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("args, says", [
    (["train", "--scene", "SCENE", "--out", "OUT", "--preset", "nonsense"], "unknown preset 'nonsense': choose from"),
    (["complete", "--run", "RUN", "--method", "ft", "--recolmap"], "--recolmap is not an option of --method ft"),
])
def test_bad_options_end_in_one_line_and_status_2(tmp_path: Path, args: list[str], says: str):
    args = [a.replace("SCENE", str(tmp_path / "scene")).replace("OUT", str(tmp_path / "out"))
            .replace("RUN", str(tmp_path / "run")) for a in args]
    (tmp_path / "scene").mkdir()
    proc = subprocess.run([sys.executable, "-m", "engine", *args], capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.strip().count("\n") == 0 and says in proc.stderr, proc.stderr


@pytest.mark.fast
def test_every_setting_of_every_command_says_what_it_means_in_help():
    """--help shows each config field's comment; a field without one would show a bare default. Every command of
    the table, and the scores' settings the completion passes on."""
    from engine.base.config_cli import field_help, load
    from engine.cli import COMMANDS
    from engine.metrics.scores import ScoreConfig

    configs = [load(c.config) for c in COMMANDS] + [ScoreConfig]
    bare = {c.__name__: [n for n, text in field_help(c).items() if not text] for c in configs}
    assert not {k: v for k, v in bare.items() if v}, f"fields without a one-line meaning: {bare}"
    assert "every Nth step" in subprocess.run([sys.executable, "-m", "engine", "train", "--help"], cwd=REPO,
                                              capture_output=True, text=True).stdout


@pytest.mark.fast
def test_the_parser_is_the_table():
    """One entry a command: each sub-command the parser knows is a row of engine.cli.COMMANDS, with its summary."""
    from engine.cli import COMMANDS, build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    assert list(sub.choices) == [c.name for c in COMMANDS]
    assert {a.dest: a.help for a in sub._choices_actions} == {c.name: c.summary for c in COMMANDS}


def test_a_declared_package_that_is_missing_is_named_with_its_install_line(living_scene: Path):
    """Not "internal error ... please report it": the package and the command that installs it, status 2."""
    code = ("import sys; sys.modules['OpenImageIO'] = None; from engine.cli import main; "
            f"sys.exit(main(['info', '--scene', {str(living_scene)!r}]))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 2, proc.stderr
    line = proc.stderr.strip().splitlines()[-1]
    assert "package OpenImageIO" in line and "pip install 'OpenImageIO==" in line and "internal" not in line


@pytest.mark.fast
def test_an_opencv_without_contrib_is_refused_by_the_inpainters_that_need_it(monkeypatch):
    import cv2

    from engine.base.errors import InputError
    from engine.inpaint.registry import create

    create("fsr")
    monkeypatch.delattr(cv2, "xphoto")
    with pytest.raises(InputError, match="fsr inpainter needs OpenCV's contrib.*opencv-contrib-python-headless=="):
        create("fsr")
    create("telea")  # the core OpenCV inpainters still work
