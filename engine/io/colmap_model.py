"""COLMAP models: read with numpy (engine.formats.colmap_files), written through pycolmap.

This is the one module that imports pycolmap, and only inside write_model: pycolmap 4.2.1 breaks zlib
when it is imported first (the next PNG write aborts the process), so zlib and cv2 are loaded before it.
"""

from __future__ import annotations

import zlib  # noqa: F401,I001  -- order matters, see the module docstring
from dataclasses import dataclass, field
from pathlib import Path

import cv2  # noqa: F401
import numpy as np

from engine.base.errors import InputError
from engine.formats import colmap_files
from engine.formats.cameras import Camera

SUPPORTED_MODELS = ("PINHOLE", "SIMPLE_PINHOLE")
MODEL_FILES = ("cameras", "images", "points3D")


@dataclass
class ColmapModel:
    """Cameras (sorted by image name) and the sparse points with their colours."""

    cameras: list[Camera]
    points: np.ndarray  # (N, 3) float64 world coordinates
    colors: np.ndarray  # (N, 3) uint8 RGB
    observations: list[list[tuple[int, float, float]]] = field(default_factory=list)
    """Per point, the (camera index, u, v) where it was seen; only used when writing."""


def read_model(model_dir: Path) -> ColmapModel:
    """Read a COLMAP model (binary or text) with numpy; one line names the missing or broken file."""
    ext = colmap_files.model_ext(model_dir)
    paths = {stem: model_dir / f"{stem}{ext}" for stem in MODEL_FILES}
    for path in paths.values():
        if not path.is_file():
            raise InputError(f"missing {path}: the COLMAP model is incomplete; re-export it")
    raw_cameras = colmap_files.read_cameras(paths["cameras"])
    raw_images = colmap_files.read_images(paths["images"])
    points, colors = colmap_files.read_points(paths["points3D"])
    if not raw_images:
        raise InputError(f"the COLMAP model in {model_dir} has no images; re-run the reconstruction")
    cameras = [_camera(model_dir, image, raw_cameras) for image in raw_images.values()]
    cameras.sort(key=lambda c: c.name)
    return ColmapModel(cameras=cameras, points=points, colors=colors)


def _camera(model_dir: Path, image: colmap_files.RawImage, cameras: dict[int, colmap_files.RawCamera]) -> Camera:
    cam = cameras.get(image.camera_id)
    if cam is None:
        raise InputError(f"image {image.name} in {model_dir} uses camera {image.camera_id}, which is missing")
    if cam.model not in SUPPORTED_MODELS:
        raise InputError(f"camera {image.camera_id} of {image.name} is {cam.model}; this step needs PINHOLE "
                         "cameras (load_scene undistorts SIMPLE_RADIAL, RADIAL and OPENCV captures first)")
    if len(cam.params) != colmap_files.PARAM_COUNTS[cam.model]:
        raise InputError(f"camera {image.camera_id} in {model_dir} has {len(cam.params)} parameters for "
                         f"{cam.model}; the model is corrupt")
    fx, fy, cx, cy = (cam.params[0], *cam.params) if cam.model == "SIMPLE_PINHOLE" else cam.params
    return Camera(name=image.name, width=cam.width, height=cam.height, fx=float(fx), fy=float(fy),
                  cx=float(cx), cy=float(cy), R=colmap_files.quat_to_rotation(image.qvec), t=image.tvec.copy())


def write_model(model_dir: Path, model: ColmapModel) -> None:
    """Write cameras.bin, images.bin and points3D.bin: one PINHOLE camera per image, with tracks."""
    import pycolmap  # after zlib and cv2, see the module docstring

    model_dir.mkdir(parents=True, exist_ok=True)
    rec = pycolmap.Reconstruction()
    per_image: list[list[tuple[int, float, float]]] = [[] for _ in model.cameras]
    for point_index, seen in enumerate(model.observations):
        for cam_index, u, v in seen:
            per_image[cam_index].append((point_index, u, v))
    track_of_point: list[list[tuple[int, int]]] = [[] for _ in range(len(model.points))]
    for index, camera in enumerate(model.cameras):
        colmap_cam = pycolmap.Camera(
            model="PINHOLE", width=camera.width, height=camera.height,
            params=[camera.fx, camera.fy, camera.cx, camera.cy], camera_id=index + 1,
        )
        rec.add_camera_with_trivial_rig(colmap_cam)
        points2d = [pycolmap.Point2D(np.array([u, v], dtype=np.float64)) for _, u, v in per_image[index]]
        image = pycolmap.Image(
            name=camera.name, camera_id=index + 1, image_id=index + 1,
            points2D=pycolmap.Point2DList(points2d),
        )
        pose = pycolmap.Rigid3d(pycolmap.Rotation3d(camera.R), camera.t)
        rec.add_image_with_trivial_frame(image, pose)
        for k, (point_index, _, _) in enumerate(per_image[index]):
            track_of_point[point_index].append((index + 1, k))
    for xyz, color, elements in zip(model.points, model.colors, track_of_point, strict=True):
        track = pycolmap.Track()
        for image_id, k in elements:
            track.add_element(image_id, k)
        rec.add_point3D(np.asarray(xyz, dtype=np.float64), track, np.asarray(color, dtype=np.uint8))
    rec.write_binary(str(model_dir))
