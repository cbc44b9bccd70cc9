"""Pinhole cameras in COLMAP's conventions, and the projections between pixels and the world.

Conventions (the classic source of 3D bugs, so stated once here):
- Poses are world-to-camera: x_cam = R @ x_world + t, with OpenCV axes (x right, y down, z forward).
- Pixel coordinates follow COLMAP: the centre of the top-left pixel is (0.5, 0.5), so pixel (col, row)
  has centre (col + 0.5, row + 0.5).
- Depth is z-depth: the z coordinate in the camera frame, not the ray length.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


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
