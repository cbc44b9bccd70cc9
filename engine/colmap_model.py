"""COLMAP models through pycolmap: the one module that imports pycolmap.

pycolmap 4.2.1 breaks zlib when it is imported first (the next PNG write aborts the process), so
zlib and cv2 are imported before it here, and nothing else in the engine imports pycolmap.
"""

from __future__ import annotations

import zlib  # noqa: F401,I001  -- order matters, see the module docstring
from dataclasses import dataclass, field
from pathlib import Path

import cv2  # noqa: F401
import numpy as np
import pycolmap

from engine.camera import Camera
from engine.errors import InputError

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


def find_model_dir(scene_root: Path) -> Path:
    """The folder holding the model: `sparse/0/` (COLMAP's layout) or `sparse/`."""
    for candidate in (scene_root / "sparse" / "0", scene_root / "sparse"):
        if any((candidate / f"cameras{ext}").is_file() for ext in (".bin", ".txt")):
            return candidate
    raise InputError(
        f"no COLMAP model in {scene_root / 'sparse'}: expected sparse/0/cameras.bin (or .txt); "
        "run COLMAP (and image_undistorter) on the images first"
    )


def read_model(model_dir: Path) -> ColmapModel:
    """Read a COLMAP model; one line names the missing or broken file."""
    ext = ".bin" if (model_dir / "cameras.bin").is_file() else ".txt"
    for stem in MODEL_FILES:
        if not (model_dir / f"{stem}{ext}").is_file():
            raise InputError(f"missing {model_dir / (stem + ext)}: the COLMAP model is incomplete; re-export it")
    if ext == ".bin":
        _check_binary_sizes(model_dir)
    try:
        rec = pycolmap.Reconstruction(str(model_dir))
    except Exception as exc:  # pycolmap raises plain RuntimeError/ValueError with C++ text
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(f"cannot read the COLMAP model in {model_dir}: {first}; re-export it") from exc
    cameras = [_camera_from_image(rec, image) for image in rec.images.values()]
    if not cameras:
        raise InputError(f"the COLMAP model in {model_dir} has no images; re-run the reconstruction")
    cameras.sort(key=lambda c: c.name)
    ids = sorted(rec.points3D.keys())
    points = np.array([rec.points3D[i].xyz for i in ids], dtype=np.float64).reshape(-1, 3)
    colors = np.array([rec.points3D[i].color for i in ids], dtype=np.uint8).reshape(-1, 3)
    return ColmapModel(cameras=cameras, points=points, colors=colors)


def _camera_from_image(rec: pycolmap.Reconstruction, image: pycolmap.Image) -> Camera:
    cam = rec.cameras[image.camera_id]
    model = cam.model.name
    if model not in SUPPORTED_MODELS:
        raise InputError(
            f"camera {image.camera_id} of {image.name} is {model}; splatfill needs PINHOLE cameras: "
            "run `colmap image_undistorter` first"
        )
    if model == "SIMPLE_PINHOLE":
        f, cx, cy = cam.params
        fx = fy = f
    else:
        fx, fy, cx, cy = cam.params
    pose = image.cam_from_world()
    return Camera(
        name=image.name, width=int(cam.width), height=int(cam.height),
        fx=float(fx), fy=float(fy), cx=float(cx), cy=float(cy),
        R=np.asarray(pose.rotation.matrix(), dtype=np.float64), t=np.asarray(pose.translation, dtype=np.float64),
    )


def _check_binary_sizes(model_dir: Path) -> None:
    """Catch truncated or empty .bin files before pycolmap reads past their end."""
    for stem in MODEL_FILES:
        path = model_dir / f"{stem}.bin"
        if path.stat().st_size < 8:
            raise InputError(f"{path} is truncated ({path.stat().st_size} bytes); re-export the COLMAP model")


def write_model(model_dir: Path, model: ColmapModel) -> None:
    """Write cameras.bin, images.bin and points3D.bin: one PINHOLE camera per image, with tracks."""
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
