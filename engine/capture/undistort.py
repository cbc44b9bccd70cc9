"""Captures with lens distortion: COLMAP's SIMPLE_RADIAL, RADIAL, OPENCV and FULL_OPENCV cameras (what
COLMAP, pycolmap, RealityScan and most capture apps write) undistorted to PINHOLE with pycolmap.

The undistorted scene is written once into the scene cache (engine.capture.scene_cache, never into the user's
folder) and reused by every later stage, with the folders that line up with the images (masks/, holes/,
depth, a generator's gt/) resampled onto the same undistorted cameras. Fisheye
models are refused with a clear message: undistorting them to a pinhole loses most of their field of view.
"""

from __future__ import annotations

import json
import shutil
import zlib  # noqa: F401,I001  -- before pycolmap, see engine.io.colmap_model
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.capture.scene_cache import cached_scene
from engine.formats import colmap_files
from engine.formats.colmap_files import find_model_dir
from engine.formats.layout import SceneLayout
from engine.io.colmap_model import SUPPORTED_MODELS

UNDISTORTED_MODELS = ("SIMPLE_RADIAL", "RADIAL", "OPENCV", "FULL_OPENCV")


def camera_models(model_dir: Path) -> set[str]:
    """The camera models a COLMAP model uses."""
    ext = colmap_files.model_ext(model_dir)
    return {c.model for c in colmap_files.read_cameras(model_dir / f"cameras{ext}").values()}


def pinhole_scene(root: Path) -> Path:
    """The folder to load for scene `root`: `root` itself when its cameras are pinhole, else its undistorted
    copy in the cache (made on first use)."""
    model_dir = find_model_dir(root)
    models = camera_models(model_dir)
    if models <= set(SUPPORTED_MODELS):
        return root
    unknown = sorted(models - set(SUPPORTED_MODELS) - set(UNDISTORTED_MODELS))
    if unknown:
        raise InputError(f"{model_dir} has {', '.join(unknown)} cameras, which splatfill cannot undistort to a "
                         f"pinhole; reconstruct with SIMPLE_RADIAL, RADIAL or OPENCV (or run colmap "
                         "image_undistorter yourself)")
    scene = SceneLayout(root)

    def build(tmp: Path) -> None:
        _undistort(model_dir, scene.images, tmp)
        _undistort_aligned(scene, model_dir, tmp)
        if scene.split_json.is_file():
            shutil.copy2(scene.split_json, SceneLayout(tmp).split_json)
        (tmp / "source.json").write_text(json.dumps({"scene": str(root.resolve()), "models": sorted(models)}))

    return cached_scene(root, "undistorted", build)


def _undistort_aligned(scene: SceneLayout, model_dir: Path, out: Path) -> None:
    """Per-view folders that line up with the distorted images (masks/, holes/, depth, a generator's gt/)
    resampled onto the undistorted cameras pycolmap chose: colours bilinear, ids and depths nearest."""
    from engine.io.colmap_model import read_model
    from engine.io.image_io import read_depth, read_png, write_depth, write_png

    ext = colmap_files.model_ext(model_dir)
    raw_cameras = colmap_files.read_cameras(model_dir / f"cameras{ext}")
    raw = {Path(i.name).stem: raw_cameras[i.camera_id] for i in colmap_files.read_images(model_dir / f"images{ext}")
           .values()}
    pinhole = {Path(c.name).stem: c for c in read_model(SceneLayout(out).sparse).cameras}
    for folder, kind in ((scene.masks, "mask"), (scene.holes, "mask"), (scene.effects, "mask"),
                         (scene.unseen, "mask"), (scene.gt, "image"), (scene.depth, "depth"),
                         (scene.gt_depth, "depth")):
        if not folder.is_dir():
            continue
        target = out / folder.name
        target.mkdir()
        for path in sorted(folder.iterdir()):
            if path.stem not in pinhole:
                shutil.copy2(path, target / path.name)  # objects.json and the like
                continue
            map_x, map_y = distortion_map(pinhole[path.stem], raw[path.stem])
            if kind == "depth":
                write_depth(target / path.name, cv2.remap(read_depth(path), map_x, map_y, cv2.INTER_NEAREST,
                                                          borderValue=float("inf")))
            else:
                picture = read_png(path, kind=kind)
                write_png(target / path.name, cv2.remap(picture, map_x, map_y, cv2.INTER_LINEAR if kind == "image"
                                                        else cv2.INTER_NEAREST))


def distortion_map(camera, raw: colmap_files.RawCamera) -> tuple[np.ndarray, np.ndarray]:
    """For each pixel of the undistorted pinhole `camera`, where it lies in the distorted image (cv2.remap
    coordinates: pixel centres at integers; COLMAP's at +0.5), by the camera model's distortion."""
    v, u = np.mgrid[0:camera.height, 0:camera.width].astype(np.float64) + 0.5
    x, y = (u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy
    p = raw.params
    r2 = x * x + y * y
    if raw.model in ("SIMPLE_RADIAL", "RADIAL"):
        fx = fy = p[0]
        cx, cy = p[1], p[2]
        radial = 1 + p[3] * r2 + (p[4] * r2 * r2 if raw.model == "RADIAL" else 0)
        xd, yd = x * radial, y * radial
    else:  # OPENCV, FULL_OPENCV
        fx, fy, cx, cy, k1, k2, p1, p2 = p[:8]
        radial = 1 + k1 * r2 + k2 * r2 * r2
        if raw.model == "FULL_OPENCV":
            k3, k4, k5, k6 = p[8:12]
            radial = (radial + k3 * r2 ** 3) / (1 + k4 * r2 + k5 * r2 * r2 + k6 * r2 ** 3)
        xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
        yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return (fx * xd + cx - 0.5).astype(np.float32), (fy * yd + cy - 0.5).astype(np.float32)


def _undistort(model_dir: Path, images: Path, out: Path) -> None:
    import pycolmap  # after zlib and cv2 (above)

    if not images.is_dir():
        raise InputError(f"missing image folder {images}: a scene needs images/ beside sparse/")
    try:
        pycolmap.undistort_images(str(out), str(model_dir), str(images))
    except Exception as exc:  # pycolmap raises plain RuntimeErrors with COLMAP's message
        raise InputError(f"pycolmap could not undistort {images} ({exc}); check that every image in the "
                         "model exists") from exc
    if not (SceneLayout(out).sparse / "cameras.bin").is_file():  # pycolmap writes the scene layout
        raise InputError(f"pycolmap wrote no undistorted model for {model_dir}; check the images and the model")
