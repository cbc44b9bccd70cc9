"""The README's "Your own capture", run as written on a capture made the way a user's is: a generated
scene's images through pycolmap's own SfM (SIMPLE_RADIAL, unknown scale and axes, no masks).

The commands are read from the README's code block, so the test fails when the README drifts. The only
additions are the test's sizes: training gets `--preset tiny --steps 300`, every stage that renders
`--device cpu`.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import REPO, make_scene

pytestmark = pytest.mark.slow


def readme_commands() -> list[str]:
    text = (REPO / "README.md").read_text()
    section = text[text.index("## Your own capture"):]
    block = section[section.index("```sh") + 5:section.index("```", section.index("```sh") + 5)]
    return [line.split("#")[0].strip() for line in block.splitlines() if line.startswith(".venv/bin/python")]


@pytest.fixture(scope="module")
def capture(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("capture")
    # SfM needs more than the tiny scenes give (20 views at 160 px registered none): 36 of these 40 register
    make_scene(root / "scene", "livingroom", ["--views", "40", "--res", "256", "--samples", "8", "--seed", "3",
                                              "--points", "3000"])
    subprocess.run([sys.executable, str(REPO / "scripts" / "make_capture.py"), "--scene", str(root / "scene"),
                    "--out", str(root / "capture"), "--keep-truth"], check=True, capture_output=True, cwd=REPO)
    return root / "capture"


def test_the_readme_user_path_runs_as_written(capture: Path, tmp_path: Path):
    commands = readme_commands()
    assert [c.split()[3] for c in commands] == ["info", "train", "segment", "remove", "holes", "inpaint",
                                                "complete"]
    assert not (capture / "masks").exists()
    run = tmp_path / "run"
    env = {**os.environ, "CAPTURE": str(capture), "RUN": str(run), "SPLATFILL_CACHE": str(tmp_path / "cache")}
    for command in commands:
        command = command.replace(".venv/bin/python", sys.executable)
        if " train " in command:
            command += " --preset tiny --steps 300"
        # telea and the other OpenCV inpainters run on the CPU; holes reads the removal's renders and renders nothing
        if command.split()[3] not in ("info", "inpaint", "holes"):
            command += " --device cpu"
        proc = subprocess.run(command, shell=True, env=env, cwd=REPO, capture_output=True, text=True)
        assert proc.returncode == 0, f"{command}\n{proc.stderr[-1500:]}"
    objects = json.loads((run / "segments" / "objects.json").read_text())
    assert objects[0]["name"] == "object_1" and len(objects[0]["box"]) == 6
    complete = next((run / "complete").iterdir())
    scores = json.loads((complete / "scores.json").read_text())
    assert scores["scores"]["psnr"] is not None and scores["scores"]["psnr"] > 10, scores["scores"]
    assert re.fullmatch(r"Init-telea\[warm\]", complete.name)
