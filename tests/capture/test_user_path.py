"""The README's "Your own capture", run as written from photos made the way a user's are: a generated scene's
images as JPEGs, half of them stored sideways with an EXIF orientation tag as phones do, nothing else (no
poses, masks or ground truth).

The commands are read from the README's code block, so the test fails when the README drifts. The only
additions are the test's sizes: training gets `--preset tiny --steps 200`, every stage that renders
`--device cpu`.
"""

from __future__ import annotations

import json
import os
import signal
import struct
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from benchmarks.capture_path import readme_commands
from engine.pictures.video import count_frames
from tests.conftest import REPO, made_once, make_scene, setup_weight

pytestmark = pytest.mark.slow
SIDE = {6: cv2.ROTATE_90_COUNTERCLOCKWISE, 8: cv2.ROTATE_90_CLOCKWISE}  # how a phone stores a portrait photo


def exif_jpeg(bgr: np.ndarray, orientation: int) -> bytes:
    """A JPEG whose EXIF says how to turn its stored pixels for display (written by hand: no EXIF writer ships)."""
    data = cv2.imencode(".jpg", bgr, [cv2.IMWRITE_JPEG_QUALITY, 95])[1].tobytes()
    tiff = b"II*\x00" + struct.pack("<IH", 8, 1) + struct.pack("<HHIHH", 0x0112, 3, 1, orientation, 0) + b"\0" * 4
    app1 = b"Exif\x00\x00" + tiff
    return data[:2] + b"\xff\xe1" + struct.pack(">H", len(app1) + 2) + app1 + data[2:]


def orbit_scene(tmp_path_factory) -> Path:
    """A livingroom's 40 orbit views at 256 px, made once per test run (the mapping and video tests read it too)."""
    return made_once(tmp_path_factory, "scene-livingroom-s3-orbit40", lambda out: make_scene(
        out, "livingroom", ["--views", "40", "--res", "256", "--samples", "8", "--seed", "3", "--points", "3000"]))


@pytest.fixture(scope="module")
def photos(tmp_path_factory) -> Path:
    """40 views of a livingroom at 256 px as JPEG photos, every other one stored sideways with its EXIF tag
    (31-36 of 40 register in SfM; 20 views at 160 px registered none)."""
    root = tmp_path_factory.mktemp("photos")
    scene = orbit_scene(tmp_path_factory)
    out = root / "photos"
    out.mkdir()
    for k, path in enumerate(sorted((scene / "images").glob("*.png"))):
        image = cv2.imread(str(path))
        orientation = (6, 8)[k // 2 % 2] if k % 2 else 1
        stored = cv2.rotate(image, SIDE[orientation]) if orientation != 1 else image
        (out / f"IMG_{k:04d}.jpg").write_bytes(exif_jpeg(stored, orientation))
    return out


def test_the_readme_user_path_runs_as_written_from_photos(photos: Path, tmp_path: Path):
    commands = readme_commands()
    assert [c.split()[3] for c in commands] == ["capture", "train", "segment", "remove", "holes", "inpaint",
                                                "complete"]
    capture, run = tmp_path / "capture", tmp_path / "run"
    env = {**os.environ, "PHOTOS": str(photos), "CAPTURE": str(capture), "RUN": str(run),
           "SPLATFILL_CACHE": str(tmp_path / "cache"), "SALIENT_WEIGHTS": str(setup_weight("u2netp.onnx"))}
    for command in commands:
        command = command.replace(".venv/bin/python", sys.executable)
        if " train " in command:
            command += " --preset tiny --steps 200"
        # telea and the other OpenCV inpainters run on the CPU; holes reads the removal's renders and renders nothing
        if command.split()[3] not in ("capture", "inpaint", "holes"):
            command += " --device cpu"
        proc = subprocess.run(command, shell=True, env=env, cwd=REPO, capture_output=True, text=True)
        assert proc.returncode == 0, f"{command}\n{proc.stderr[-1500:]}"
    report = json.loads((capture / "capture.json").read_text())
    # 31 to 36 of 40 registered in runs on 2 cores (pycolmap's mapping varies); the sideways half alone is 20,
    # so a capture that ignored EXIF orientation stays near 20
    assert report["registered"] >= 26 and report["images"] == 40, report
    sizes = {cv2.imread(str(p)).shape[:2] for p in (capture / "images").iterdir()}
    assert all(h < w for h, w in sizes), sizes  # every photo upright (landscape), the sideways ones turned back
    objects = json.loads((run / "segments" / "objects.json").read_text())
    assert objects[0]["name"] == "object_1" and len(objects[0]["box"]) == 6
    complete = next((run / "complete").iterdir())
    assert complete.name == "Ref-coherence[warm]", complete  # the defaults' fill (engine.base.defaults)
    scores = json.loads((complete / "scores.json").read_text())
    assert scores["scores"]["psnr_outside"] > 15 and scores["scores"]["m_psnr"] is None, scores["scores"]
    assert "no gt/" in scores["unavailable"]["m_psnr"]
    assert len(list((complete / "renders").iterdir())) == len(json.loads((run / "metrics.json").read_text())
                                                              ["psnr_per_view"])
    assert count_frames(complete / "turntable" / "turntable.mp4") == 48


def test_a_stopped_capture_continues_where_it_stopped(photos: Path, tmp_path: Path):
    """SIGTERM while SfM matches: exit 130, the features kept; the same command again finishes without
    extracting them a second time."""
    out = tmp_path / "capture"
    command = [sys.executable, "-m", "engine", "capture", "--images", str(photos), "--out", str(out)]
    env = {**os.environ, "SPLATFILL_PROGRESS": "json"}
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=REPO)
    for line in proc.stdout:
        if json.loads(line).get("phase") == "matches":
            proc.send_signal(signal.SIGTERM)
            break
    stderr = proc.communicate()[1]
    assert proc.returncode == 130, stderr
    assert "run the same command again" in stderr.splitlines()[-1]
    assert not (out / "capture.json").exists()
    again = subprocess.run(command, capture_output=True, text=True, env=env, cwd=REPO)
    assert again.returncode == 0, again.stderr[-1500:]
    report = json.loads((out / "capture.json").read_text())
    assert "features" not in report["phases"] and "matches" in report["phases"], report
