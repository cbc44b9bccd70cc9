"""COLMAP cameras <-> Blender cameras, as numbers (no bpy, so the tests check it without Blender).

COLMAP (and the engine's cameras.json) stores world-to-camera R, t with OpenCV axes (x right, y down,
z forward) and PINHOLE intrinsics fx, fy, cx, cy in pixels. Blender's camera looks down its -Z with +Y up,
measures its lens against a sensor (the larger image side with the sensor fit below), its principal-point
offset as a shift in units of the larger image side, and a non-square pixel as the scene's pixel aspect.
The conversion is the one ../shared/reference/blender.md checked to 0 px against COLMAP's projection.
"""

from __future__ import annotations

import numpy as np

SENSOR_MM = 36.0
FLIP_YZ = np.diag([1.0, -1.0, -1.0])  # OpenCV camera axes <-> Blender camera axes


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
