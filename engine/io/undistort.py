"""Captures with lens distortion: COLMAP's SIMPLE_RADIAL, RADIAL, OPENCV and FULL_OPENCV cameras (what
COLMAP, pycolmap, RealityScan and most capture apps write) undistorted to PINHOLE with pycolmap.

The undistorted scene is written once into the scene cache (engine.io.scene_cache, never into the user's
folder) and reused by every later stage. Fisheye
models are refused with a clear message: undistorting them to a pinhole loses most of their field of view.
"""

from __future__ import annotations

import json
import shutil
import zlib  # noqa: F401,I001  -- before pycolmap, see engine.io.colmap_model
from pathlib import Path

import cv2  # noqa: F401

from engine.base.errors import InputError
from engine.formats import colmap_files
from engine.formats.colmap_files import find_model_dir
from engine.formats.layout import SceneLayout
from engine.io.colmap_model import SUPPORTED_MODELS
from engine.io.scene_cache import cached_scene

UNDISTORTED_MODELS = ("SIMPLE_RADIAL", "RADIAL", "OPENCV", "FULL_OPENCV")


def camera_models(model_dir: Path) -> set[str]:
    """The camera models a COLMAP model uses."""
    ext = ".bin" if (model_dir / "cameras.bin").is_file() else ".txt"
    try:
        return {c.model for c in colmap_files.read_cameras(model_dir / f"cameras{ext}").values()}
    except (OSError, ValueError, IndexError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot parse {model_dir / f'cameras{ext}'} ({exc}); re-export the model") from exc


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
    aligned = [p.name for p in (scene.masks, scene.depth, scene.gt, scene.gt_depth, scene.holes) if p.is_dir()]
    if aligned:
        raise InputError(f"{root} has {', '.join(aligned)}/ beside distorted cameras, which would no longer line "
                         "up after undistortion; undistort the capture with colmap image_undistorter instead")

    def build(tmp: Path) -> None:
        _undistort(model_dir, scene.images, tmp)
        if scene.split_json.is_file():
            shutil.copy2(scene.split_json, SceneLayout(tmp).split_json)
        (tmp / "source.json").write_text(json.dumps({"scene": str(root.resolve()), "models": sorted(models)}))

    return cached_scene(root, "undistorted", build)


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
