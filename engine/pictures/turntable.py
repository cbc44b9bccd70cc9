"""`python -m engine turntable`: a before/after turntable around a removed object, as one H.264 MP4.

One engine command, so scripts/turntable.py and the add-on's Turntable operator run the same thing (the
add-on runs one engine process per operator, with its progress bar and Esc). The orbit circles the removed
object's centre (the mean of the Gaussians the removal took away) at the
median distance and height of the scene's own cameras, around their mean up direction, with the first
camera's intrinsics; `cameras` follows any cameras.json instead (the script and the add-on write a Blender
camera's path there). Both scenes (before: the run's point_cloud.ply; after: the removed scene, or any .ply
such as a completed run's) are rendered from the same cameras, put side by side with labels, and written as
OUT/turntable.mp4 (engine.pictures.video, decoded again and counted before it is kept). The folder is written
atomically; `keep_frames` keeps frames/, before/ and after/ beside the MP4.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import emit
from engine.formats.cameras import camera_record, camera_to_world
from engine.formats.checks import read_json
from engine.formats.colmap_files import find_model_dir
from engine.formats.layout import RemovedLayout, RunLayout
from engine.io.colmap_model import read_model
from engine.io.ply_io import load_ply
from engine.pictures.compare_sheet import compare_frames
from engine.pictures.video import write_mp4
from engine.render.render_views import render_to_folder


@dataclass
class TurntableConfig:
    run: str = ""  # the training run
    removed: str = ""  # the removal's folder (default RUN/removed)
    out: str = ""  # a new folder for cameras.json and turntable.mp4
    after: str = ""  # .ply shown as "after" (default: the removed scene)
    cameras: str = ""  # a cameras.json to follow instead of the orbit (a Blender camera's path)
    frames: int = 48  # frames around the orbit
    fps: int = 24  # frames a second of the MP4
    keep_frames: bool = False  # keep frames/, before/ and after/ beside the MP4
    device: str = "auto"  # auto | cuda | cpu


def object_centre(run: RunLayout, removed: RemovedLayout) -> np.ndarray:
    """Where the removed object was: the mean of the Gaussians the removal took away (those of the run that the
    removed scene no longer has; removal keeps the others' positions as they were), whatever chose them: an
    identity, a segment, a box or the visual hull."""
    before, after = load_ply(run.point_cloud)["means"].numpy(), load_ply(removed.point_cloud)["means"].numpy()
    rows = np.dtype((np.void, before.dtype.itemsize * 3))
    gone = ~np.isin(np.ascontiguousarray(before).view(rows).ravel(), np.ascontiguousarray(after).view(rows).ravel())
    if not gone.any():
        raise InputError(f"{removed.point_cloud} removed nothing from {run.point_cloud}: pass --cameras")
    return before[gone].mean(0).astype(np.float64)


def orbit(records: list[dict], centre: np.ndarray, frames: int) -> list[dict]:
    """`frames` cameras on a circle around `centre`, at the scene cameras' median distance and height."""
    R = np.array([r["R"] for r in records])
    centres = np.array([camera_to_world(r["R"], r["t"])[:3, 3] for r in records])
    up = -R[:, 1, :].mean(0)  # a camera's -y axis (OpenCV) points up in the world
    up /= np.linalg.norm(up)
    offsets = centres - centre
    height = float(np.median(offsets @ up))
    flat = offsets - np.outer(offsets @ up, up)
    radius = float(np.median(np.linalg.norm(flat, axis=1)))
    e1 = flat[0] / np.linalg.norm(flat[0])
    e2 = np.cross(up, e1)
    first = records[0]
    out = []
    for k in range(frames):
        angle = 2 * np.pi * k / frames
        position = centre + height * up + radius * (np.cos(angle) * e1 + np.sin(angle) * e2)
        z = (centre - position) / np.linalg.norm(centre - position)
        x = np.cross(z, up)
        x /= np.linalg.norm(x)
        rotation = np.stack([x, np.cross(z, x), z])
        out.append({**{key: first[key] for key in ("width", "height", "fx", "fy", "cx", "cy")},
                    "name": f"{k:04d}.png", "R": rotation.tolist(), "t": (-rotation @ position).tolist()})
    return out


def _cameras(config: TurntableConfig, run: RunLayout, removed: RemovedLayout) -> list[dict]:
    if config.cameras:
        records = read_json(Path(config.cameras))
        if not isinstance(records, list) or not records:
            raise InputError(f"{config.cameras} holds no list of cameras: write it with the add-on or "
                             "`python -m engine cameras`")
        return records
    if config.frames < 1:
        raise InputError(f"--frames {config.frames}: a turntable needs at least one frame")
    if not removed.point_cloud.is_file():
        raise InputError(f"{removed.point_cloud} missing: run `python -m engine remove` first, or name --removed")
    scene = Path(read_json(run.config_json)["scene"])
    records = [camera_record(c) for c in read_model(find_model_dir(scene)).cameras]
    return orbit(records, object_centre(run, removed), config.frames)


def make_turntable(config: TurntableConfig) -> Path:
    """Write config.out (cameras.json, turntable.mp4); returns the MP4's path."""
    run = RunLayout(config.run)
    for needed in (run.config_json, run.point_cloud):
        if not needed.is_file():
            raise InputError(f"{needed} missing: {run.root} is not a finished training run")
    removed = RemovedLayout(config.removed) if config.removed else run.removed
    after = Path(config.after) if config.after else removed.point_cloud
    if not after.is_file():
        raise InputError(f"{after} missing: name the scene to show after the removal with --after")
    out = Path(config.out)
    with atomic_output_dir(out) as tmp:
        records = _cameras(config, run, removed)
        (tmp / "cameras.json").write_text(json.dumps(records, indent=1))
        for name, ply in (("before", run.point_cloud), ("after", after)):
            render_to_folder(ply, tmp / "cameras.json", tmp / name, config.device)
        names = [r["name"] for r in records]
        frames = compare_frames([("before", tmp / "before"), ("after", tmp / "after")], names, tmp / "frames")
        write_mp4([frames / n for n in names], tmp / "turntable.mp4", config.fps)
        if not config.keep_frames:
            for folder in ("frames", "before", "after"):
                shutil.rmtree(tmp / folder)
    video = out / "turntable.mp4"
    emit("done", stage="turntable", out=str(video), frames=len(records))
    return video
