"""cameras.json: a list of cameras in COLMAP's conventions (world-to-camera R, t with OpenCV axes, PINHOLE
fx, fy, cx, cy in pixels), one record per view. It is how cameras cross between Blender's Python and the
engine: make_scene.py writes it for the generator, the add-on reads it to import a scene's cameras
(`python -m engine cameras`) and writes it for turntables (`python -m engine render`)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from engine.base.errors import InputError
from engine.formats.cameras import Camera


def camera_record(camera: Camera) -> dict:
    return {"name": camera.name, "width": camera.width, "height": camera.height, "fx": camera.fx, "fy": camera.fy,
            "cx": camera.cx, "cy": camera.cy, "R": np.asarray(camera.R).tolist(), "t": np.asarray(camera.t).tolist()}


def write_cameras_json(cameras: list[Camera], path: Path) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps([camera_record(c) for c in cameras], indent=1))
    tmp.replace(path)
    return path


def read_cameras_json(path: Path) -> list[Camera]:
    try:
        entries = json.loads(Path(path).read_text())
        return [Camera(name=e["name"], width=int(e["width"]), height=int(e["height"]), fx=float(e["fx"]),
                       fy=float(e["fy"]), cx=float(e["cx"]), cy=float(e["cy"]),
                       R=np.array(e["R"], dtype=np.float64), t=np.array(e["t"], dtype=np.float64))
                for e in entries]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise InputError(f"cannot read cameras from {path} ({exc}); write it with the add-on or make_scene.py") from exc
