"""Pinhole cameras in COLMAP's conventions: projections between pixels and the world, cameras.json, and the
conversion to and from Blender cameras. Numpy only: the engine and Blender's Python share this module.

Conventions (the classic source of 3D bugs, so stated once here):
- Poses are world-to-camera: x_cam = R @ x_world + t, with OpenCV axes (x right, y down, z forward).
- Pixel coordinates follow COLMAP: the centre of the top-left pixel is (0.5, 0.5), so pixel (col, row)
  has centre (col + 0.5, row + 0.5).
- Depth is z-depth: the z coordinate in the camera frame, not the ray length.
- cameras.json is a list of such cameras (PINHOLE fx, fy, cx, cy in pixels, R, t), one record per view. It
  is how cameras cross between Blender's Python and the engine: make_scene.py writes it for the generator,
  the add-on reads it to import a scene's cameras (`python -m engine cameras`) and writes it for turntables
  (`python -m engine render`).
- Blender's camera looks down its -Z with +Y up, measures its lens against a sensor (the larger image side
  with the sensor fit below), its principal-point offset as a shift in units of the larger image side, and
  a non-square pixel as the scene's pixel aspect. This conversion projects to within 0 px of COLMAP's own
  projection.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from .checks import check_intrinsics, check_pose, read_json

SENSOR_MM = 36.0
FLIP_YZ = np.diag([1.0, -1.0, -1.0])  # OpenCV camera axes <-> Blender camera axes


@dataclass(frozen=True)
class Camera:
    """One view: intrinsics, world-to-camera pose and the image file name it belongs to."""

    name: str
    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    R: np.ndarray  # (3, 3) world-to-camera rotation
    t: np.ndarray  # (3,) world-to-camera translation

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) in pixels, as image headers give it."""
        return self.width, self.height

    @property
    def K(self) -> np.ndarray:
        """(3, 3) intrinsic matrix."""
        return np.array([[self.fx, 0, self.cx], [0, self.fy, self.cy], [0, 0, 1]], dtype=np.float64)

    @property
    def world_to_camera(self) -> np.ndarray:
        """(4, 4) world-to-camera matrix."""
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = self.R, self.t
        return m

    @property
    def camera_to_world(self) -> np.ndarray:
        """(4, 4) camera-to-world matrix (OpenCV axes)."""
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = self.R.T, self.center
        return m

    @property
    def center(self) -> np.ndarray:
        """(3,) camera centre in world coordinates."""
        return -self.R.T @ self.t


def pixel_grid(camera: Camera) -> tuple[np.ndarray, np.ndarray]:
    """Pixel-centre coordinates (u, v), each (H, W) float64."""
    u = np.arange(camera.width) + 0.5
    v = np.arange(camera.height) + 0.5
    return np.meshgrid(u, v)


def backproject(camera: Camera, u: np.ndarray, v: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """Pixels (u, v) at z-depth `depth` to world points, shape (..., 3)."""
    x = (u - camera.cx) / camera.fx * depth
    y = (v - camera.cy) / camera.fy * depth
    cam = np.stack([x, y, depth], axis=-1)
    return (cam - camera.t) @ camera.R  # R^T (x - t), row-vector form


def project(camera: Camera, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World points (..., 3) to pixel coordinates u, v and camera z, each (...)."""
    cam = points @ camera.R.T + camera.t
    z = cam[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = camera.fx * cam[..., 0] / z + camera.cx
        v = camera.fy * cam[..., 1] / z + camera.cy
    return u, v, z


def sample_nearest(image: np.ndarray, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values of `image` (H, W[, C]) at the pixels containing (u, v), and which (u, v) lie inside.

    Outside pixels (and non-finite coordinates) get the value at (0, 0); use the returned mask.
    """
    h, w = image.shape[:2]
    col, row = _pixel_index(u), _pixel_index(v)
    inside = (col >= 0) & (col < w) & (row >= 0) & (row < h)
    return image[np.where(inside, row, 0), np.where(inside, col, 0)], inside


def _pixel_index(x: np.ndarray) -> np.ndarray:
    """floor(x) as int64; non-finite or huge values become -1, which lies outside every image."""
    x = np.nan_to_num(np.asarray(x, dtype=np.float64), nan=-1.0, posinf=-1.0, neginf=-1.0)
    return np.floor(np.clip(x, -1.0, 1e9)).astype(np.int64)


def mean_up(rotations: np.ndarray) -> np.ndarray | None:
    """The cameras' mean up direction (unit), or None when they agree on none. `rotations` (K, 3, 3) are
    world-to-camera; a camera's up is its -y axis (OpenCV), which is -R[1] in the world. People hold a
    camera level, so this is the scene's up whatever axes SfM picked."""
    ups = -np.asarray(rotations).reshape(-1, 3, 3)[:, 1, :]
    up = ups.sum(axis=0)
    norm = np.linalg.norm(up)
    return up / norm if norm > 1e-9 * max(len(ups), 1) else None


def upright_rotation(rotations: np.ndarray) -> np.ndarray:
    """(3, 3) the rotation that turns the cameras' mean up direction into +Z, Blender's up, by the shortest
    arc. SfM picks its own axes (a capture often comes in tilted by tens of degrees); a generated scene's
    cameras are upright already and give (nearly) the identity."""
    up = mean_up(rotations)
    if up is None:
        return np.eye(3)
    z = np.array([0.0, 0.0, 1.0])
    axis, cos = np.cross(up, z), float(up @ z)
    if np.linalg.norm(axis) < 1e-12:
        return np.eye(3) if cos > 0 else np.diag([1.0, -1.0, -1.0])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + k + k @ k / (1.0 + cos)  # Rodrigues with the unnormalised axis (|axis| = sin)


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
    """Cameras a renderer can use: sizes within the pixel limit, positive focal lengths, rotations."""
    entries = read_json(path)
    if not isinstance(entries, list) or not entries:
        raise InputError(f"{path} holds no list of cameras; write it with the add-on or make_scene.py")
    cameras = []
    try:
        for e in entries:
            name = str(e["name"])
            width, height, fx, fy, cx, cy = check_intrinsics(e["width"], e["height"], e["fx"], e["fy"], e["cx"],
                                                             e["cy"], path, name)
            R, t = check_pose(e["R"], e["t"], path, name)
            cameras.append(Camera(name=name, width=width, height=height, fx=fx, fy=fy, cx=cx, cy=cy, R=R, t=t))
    except (KeyError, TypeError) as exc:
        raise InputError(f"cannot read cameras from {path} (missing {exc}); write it with the add-on or "
                         "make_scene.py") from exc
    return cameras


def blender_settings(fx: float, fy: float, cx: float, cy: float, width: int, height: int) -> dict:
    """Camera data and render settings that make Blender project like the PINHOLE camera."""
    landscape = width >= height
    side = max(width, height)
    return {
        "sensor_fit": "HORIZONTAL" if landscape else "VERTICAL",
        "sensor_width": SENSOR_MM, "sensor_height": SENSOR_MM,
        "lens": fx * SENSOR_MM / width if landscape else fy * SENSOR_MM / height,
        "shift_x": (width / 2 - cx) / side * (1.0 if landscape else fy / fx),
        "shift_y": (cy - height / 2) / side * (fx / fy if landscape else 1.0),
        "pixel_aspect": (1.0, fx / fy) if landscape else (fy / fx, 1.0),
        "resolution": (int(width), int(height)),
    }


def camera_to_world(R: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Blender's matrix_world (4x4) for the COLMAP world-to-camera pose R, t."""
    pose = np.eye(4)
    pose[:3, :3] = np.asarray(R).T @ FLIP_YZ
    pose[:3, 3] = -np.asarray(R).T @ np.asarray(t)
    return pose


def colmap_record(name: str, matrix_world: np.ndarray, lens: float, sensor_width: float, sensor_height: float,
                  sensor_fit: str, shift_x: float, shift_y: float, width: int, height: int,
                  pixel_aspect: tuple[float, float] = (1.0, 1.0)) -> dict:
    """The inverse: a Blender camera (any sensor fit, shift and pixel aspect) as a cameras.json record."""
    aspect_x, aspect_y = pixel_aspect
    fit = sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if width * aspect_x >= height * aspect_y else "VERTICAL"
    if fit == "HORIZONTAL":
        fx = lens / sensor_width * width
        fy = fx * aspect_x / aspect_y
    else:
        fy = lens / (sensor_height if sensor_fit == "VERTICAL" else sensor_width) * height
        fx = fy * aspect_y / aspect_x
    side = max(width, height)
    landscape = fit == "HORIZONTAL"
    cx = width / 2 - shift_x * side / (1.0 if landscape else fy / fx)
    cy = height / 2 + shift_y * side / (fx / fy if landscape else 1.0)
    m = np.asarray(matrix_world, dtype=np.float64)
    rotation = (m[:3, :3] / np.linalg.norm(m[:3, :3], axis=0)) @ FLIP_YZ  # camera-to-world, OpenCV axes
    R = rotation.T
    t = -R @ m[:3, 3]
    return {"name": name, "width": int(width), "height": int(height), "fx": float(fx), "fy": float(fy),
            "cx": float(cx), "cy": float(cy), "R": R.tolist(), "t": t.tolist()}
