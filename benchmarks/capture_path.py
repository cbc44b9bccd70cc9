"""The README's "Your own capture" on a folder of real photos, as written, timed stage by stage, and the pictures
to look at: the segments, holes and inpainting sheets, removed views, completed views under the removed render of
the same views, and a strip of turntable frames.

    PYTHONPATH=. python benchmarks/capture_path.py PHOTOS WORK RESULTS

Runs each command of the README's block (read from README.md, so it measures what users run) with PHOTOS,
CAPTURE=WORK/capture and RUN=WORK/run, nothing added. RESULTS/<name>.json holds the seconds per stage, the commit,
the GPU, capture.json, the subject's line of segments.json, removal.json's counts and scores.json;
RESULTS/<name>_*.jpg the pictures (small: about 1,000 px wide).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import cv2
import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from engine.base.versions import code_commit  # noqa: E402
from engine.formats.layout import CaptureLayout, CompleteLayout, RunLayout  # noqa: E402

WIDTH = 1000


def readme_commands() -> list[str]:
    text = (REPO / "README.md").read_text()
    section = text[text.index("## Your own capture"):]
    block = section[section.index("```sh") + 5:section.index("```", section.index("```sh") + 5)]
    return [line.split("#")[0].strip() for line in block.splitlines() if line.startswith(".venv/bin/python")]


def strip(images: list[np.ndarray], width: int = WIDTH) -> np.ndarray:
    """Images side by side at one height, scaled to `width` in all."""
    height = min(i.shape[0] for i in images)
    row = np.concatenate([cv2.resize(i, (round(i.shape[1] * height / i.shape[0]), height)) for i in images], 1)
    return cv2.resize(row, (width, round(row.shape[0] * width / row.shape[1])), interpolation=cv2.INTER_AREA)


def pick(folder: Path, count: int) -> list[np.ndarray]:
    files = sorted(folder.iterdir())
    return [cv2.imread(str(files[k])) for k in np.linspace(0, len(files) - 1, min(count, len(files))).astype(int)]


def turntable_frames(video: Path, count: int) -> list[np.ndarray]:
    capture, frames = cv2.VideoCapture(str(video)), []
    while True:
        ok, frame = capture.read()
        if not ok:
            break
        frames.append(frame)
    return [frames[k] for k in np.linspace(0, len(frames) - 1, count).astype(int)] if frames else []


def main() -> int:
    photos, work, results = (Path(a) for a in sys.argv[1:4])
    name = photos.parent.name if photos.name == "images" else photos.name
    results.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "PHOTOS": str(photos), "CAPTURE": str(work / "capture"), "RUN": str(work / "run")}
    seconds: dict[str, float] = {}
    for command in readme_commands():
        stage = command.split()[3]
        command = command.replace(".venv/bin/python", sys.executable)
        start = time.perf_counter()
        proc = subprocess.run(command, shell=True, env=env, cwd=REPO, capture_output=True, text=True)
        seconds[stage] = round(time.perf_counter() - start, 1)
        print(f"{name} {stage} {seconds[stage]} s rc {proc.returncode}: {proc.stderr.strip().splitlines()[-1:]}",
              flush=True)
        if proc.returncode != 0:
            break
    run = RunLayout(work / "run")
    record = {"capture": name, "commit": code_commit(), "gpu": _gpu(), "seconds": seconds,
              "total_seconds": round(sum(seconds.values()), 1), "commands": readme_commands()}
    for key, path in (("capture_report", CaptureLayout(work / "capture").report), ("train", run.metrics_json),
                      ("segments", run.segments.report), ("removal", run.removed.report)):
        if path.is_file():
            data = json.loads(path.read_text())
            record[key] = {k: v for k, v in data.items() if k != "config"}
    finished = [CompleteLayout(p.parent) for p in sorted(run.root.glob("*/*/scores.json"))]
    if finished:
        record["complete"] = json.loads(finished[0].scores_json.read_text())
    (results / f"{name}.json").write_text(json.dumps(record, indent=1))
    _pictures(run, finished[0] if finished else None, results / name)
    return 0 if len(seconds) == len(readme_commands()) and finished else 1


def _pictures(run: RunLayout, complete: CompleteLayout | None, prefix: Path) -> None:
    quality = [cv2.IMWRITE_JPEG_QUALITY, 85]
    sheets = [("segments", run.segments.sheet), ("holes", run.holes.sheet),
              *(("inpainted", p) for p in sorted(run.root.glob("inpainted/*/sheet_test.png"))[:1])]
    for what, sheet in sheets:
        if sheet.is_file():
            image = cv2.imread(str(sheet))
            cv2.imwrite(f"{prefix}_{what}.jpg", cv2.resize(image, (WIDTH // 2, round(image.shape[0] * WIDTH / 2 /
                                                                                      image.shape[1]))), quality)
    if run.removed.images.is_dir():
        cv2.imwrite(f"{prefix}_removed.jpg", strip(pick(run.removed.images, 6)), quality)
    if complete is not None:
        cv2.imwrite(f"{prefix}_completed.jpg", before_after(run.removed.images, complete.renders), quality)
        videos = sorted(complete.root.glob("*/*.mp4"))
        frames = turntable_frames(videos[0], 4) if videos else []
        if frames:
            cv2.imwrite(f"{prefix}_turntable.jpg", strip(frames), quality)


def before_after(removed: Path, completed: Path, count: int = 4) -> np.ndarray:
    """The completed views (below) under the removed scene's render of the same views (above): what completion
    changed, including any blur the removed scene did not have, is seen by looking down a column."""
    files = sorted(completed.iterdir())
    files = [files[k] for k in np.linspace(0, len(files) - 1, min(count, len(files))).astype(int)]
    rows = [[cv2.imread(str(removed / f.name)) for f in files if (removed / f.name).is_file()],
            [cv2.imread(str(f)) for f in files if (removed / f.name).is_file()]]
    return np.concatenate([strip(row) for row in rows], 0) if rows[0] else strip([cv2.imread(str(f)) for f in files])


def _gpu() -> str | None:
    try:
        import torch

        return torch.cuda.get_device_name() if torch.cuda.is_available() else None
    except ImportError:
        return None


if __name__ == "__main__":
    sys.exit(main())
