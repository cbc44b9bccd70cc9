"""Scenes at a lower resolution, as 3DGS's `-r 2|4|8`: a capture's 12-megapixel photos train at a quarter
of their size. The downscaled scene is a whole scene folder in the scene cache (engine.capture.scene_cache):
images and ground truth resized by area, masks, holes and depth by nearest neighbour (ids and z-depth must
not blend), and the COLMAP model's intrinsics scaled with the image size, so every later stage that copies
the scene (completion's training scene) stays consistent."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.capture.scene_cache import cached_scene
from engine.formats.cameras import Camera
from engine.formats.colmap_files import find_model_dir
from engine.formats.layout import SceneLayout
from engine.io.colmap_model import read_model, write_model
from engine.io.image_io import exr_name, read_depth, read_png, write_depth, write_png

FACTORS = (1, 2, 4, 8)


def downscaled_scene(root: Path, factor: int) -> Path:
    """`root` itself for factor 1, else its copy at 1/factor of the size (made on first use)."""
    if factor not in FACTORS:
        raise InputError(f"--resolution {factor} unknown: use one of {', '.join(map(str, FACTORS))} (as 3DGS's -r)")
    if factor == 1:
        return root
    return cached_scene(root, f"resolution{factor}", lambda tmp: _write(root, factor, tmp))


def scaled_camera(camera: Camera, factor: int) -> Camera:
    """The camera at round(W / factor) x round(H / factor); focal lengths and principal point scale with
    the exact size ratio (pixel centres stay at +0.5, COLMAP's convention)."""
    width, height = max(1, round(camera.width / factor)), max(1, round(camera.height / factor))
    sx, sy = width / camera.width, height / camera.height
    return dataclasses.replace(camera, width=width, height=height, fx=camera.fx * sx, fy=camera.fy * sy,
                               cx=camera.cx * sx, cy=camera.cy * sy)


def _write(root: Path, factor: int, out: Path) -> None:
    source, target = SceneLayout(root), SceneLayout(out)
    model = read_model(find_model_dir(root))
    cameras = [scaled_camera(c, factor) for c in model.cameras]
    write_model(target.sparse / "0", dataclasses.replace(model, cameras=cameras))
    for camera in cameras:
        size = (camera.width, camera.height)
        _resize(source.images / camera.name, target.images / camera.name, size, cv2.INTER_AREA, required=True)
        _resize(source.gt / camera.name, target.gt / camera.name, size, cv2.INTER_AREA)
        png = str(Path(camera.name).with_suffix(".png"))
        _resize(source.masks / png, target.masks / png, size, cv2.INTER_NEAREST, kind="mask")
        _resize(source.holes / png, target.holes / png, size, cv2.INTER_NEAREST, kind="mask")
        _resize(source.effects / png, target.effects / png, size, cv2.INTER_NEAREST, kind="mask")
        _resize(source.unseen / png, target.unseen / png, size, cv2.INTER_NEAREST, kind="mask")
        for folder, copy in ((source.depth, target.depth), (source.gt_depth, target.gt_depth)):
            path = folder / exr_name(camera.name)
            if path.is_file():
                depth = read_depth(path)
                write_depth(copy / exr_name(camera.name), cv2.resize(depth, size, interpolation=cv2.INTER_NEAREST))
    for path, copy in ((source.objects_json, target.objects_json), (source.split_json, target.split_json),
                       (source.scene_json, target.scene_json)):
        if path.is_file():
            copy.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(path, copy)


def _resize(path: Path, out: Path, size: tuple[int, int], interpolation: int, kind: str = "image",
            required: bool = False) -> None:
    if not path.is_file() and not required:
        return  # optional ground truth; read_png names a missing required image
    image = read_png(path, kind)
    write_png(out, np.ascontiguousarray(cv2.resize(image, size, interpolation=interpolation)))
