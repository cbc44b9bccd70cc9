"""Re-run COLMAP (through pycolmap) on a completion's training images: the paper's COLMAP ablation.

The paper's Init does not re-run COLMAP on the inpainted images and shows why (its bear ablation: with
the object gone there are fewer features to register the views by, and the new poses blur the result).
`complete --recolmap` reproduces that arm: SIFT features of the training images, exhaustive matching, and
incremental mapping with the original intrinsics held fixed (only poses and points are re-estimated).
The new model lives in its own frame and scale, so it is brought into the original's by the similarity
that best maps its camera centres onto the original ones (Umeyama 1991); the test cameras keep their
original poses, so the scores compare like with like. Training views COLMAP could not register are left
out of training, and the report says how many, with the pose error of the others.
"""

from __future__ import annotations

import json
import zlib  # noqa: F401,I001  -- before pycolmap, see engine.io.colmap_model
from dataclasses import dataclass, replace
from pathlib import Path

import cv2  # noqa: F401
import numpy as np

from engine.base.errors import InputError
from engine.formats.cameras import Camera
from engine.formats.colmap_files import find_model_dir
from engine.formats.layout import SceneLayout
from engine.io.colmap_model import ColmapModel, read_model, write_model

MIN_REGISTERED = 0.5  # below this share of training views the new model is no scene to train on


@dataclass
class Similarity:
    """x_original = scale * rotation @ x_new + shift."""

    scale: float
    rotation: np.ndarray  # (3, 3)
    shift: np.ndarray  # (3,)

    def points(self, x: np.ndarray) -> np.ndarray:
        return self.scale * x @ self.rotation.T + self.shift

    def camera(self, camera: Camera) -> Camera:
        """The same view in the original frame: camera coordinates scaled by `scale` project identically."""
        rotation = camera.R @ self.rotation.T
        return replace(camera, R=rotation, t=self.scale * camera.t - rotation @ self.shift)


def umeyama(new: np.ndarray, original: np.ndarray) -> Similarity:
    """The least-squares similarity taking points `new` (N, 3) onto `original` (N, 3), N >= 3."""
    mu_n, mu_o = new.mean(0), original.mean(0)
    dn, do = new - mu_n, original - mu_o
    u, s, vt = np.linalg.svd(do.T @ dn / len(new))
    sign = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt)) or 1.0])
    rotation = u @ sign @ vt
    scale = float(np.trace(np.diag(s) @ sign) / (dn ** 2).sum(1).mean())
    return Similarity(scale, rotation, mu_o - scale * rotation @ mu_n)


def reconstruct(images: Path, names: list[str], intrinsics: Camera, work: Path) -> ColmapModel:
    """SfM of `names` in `images` with one fixed PINHOLE camera; the largest model, as read by our reader."""
    import pycolmap

    work.mkdir(parents=True, exist_ok=True)
    database = work / "database.db"
    database.unlink(missing_ok=True)
    reader = pycolmap.ImageReaderOptions()
    reader.camera_model = "PINHOLE"
    reader.camera_params = ",".join(str(v) for v in (intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy))
    pycolmap.extract_features(database, images, image_names=names, camera_mode=pycolmap.CameraMode.SINGLE,
                              reader_options=reader, device=pycolmap.Device.cpu)
    pycolmap.match_exhaustive(database, device=pycolmap.Device.cpu)
    options = pycolmap.IncrementalPipelineOptions()
    options.ba_refine_focal_length = False
    options.ba_refine_principal_point = False
    options.ba_refine_extra_params = False
    models = pycolmap.incremental_mapping(database, images, work / "sparse", options=options)
    if not models:
        raise InputError(f"COLMAP registered none of the {len(names)} training images in {images}: too few "
                         "features match (run without --recolmap)")
    best = max(models, key=lambda k: models[k].num_reg_images())
    out = work / "model"
    out.mkdir(exist_ok=True)
    models[best].write_binary(str(out))
    return read_model(out)


def rerun_colmap(scene_dir: Path, train_names: list[str], work: Path) -> dict:
    """Replace scene_dir's model by one re-estimated from its training images (see the module docstring);
    returns the report: views registered, alignment residual and pose errors against the original."""
    model_dir = find_model_dir(scene_dir)
    original = read_model(model_dir)
    by_name = {c.name: c for c in original.cameras}
    new = reconstruct(SceneLayout(scene_dir).images, train_names, by_name[train_names[0]], work)
    registered = [c for c in new.cameras if c.name in by_name and c.name in train_names]
    if len(registered) < max(3, MIN_REGISTERED * len(train_names)):
        raise InputError(f"COLMAP registered {len(registered)} of {len(train_names)} training images of "
                         f"{scene_dir}: too few to train on (run without --recolmap)")
    align = umeyama(np.array([c.center for c in registered]), np.array([by_name[c.name].center for c in registered]))
    aligned = {c.name: align.camera(c) for c in registered}
    extent = np.ptp(np.array([c.center for c in original.cameras]), axis=0).max()
    centre_error = [float(np.linalg.norm(aligned[n].center - by_name[n].center)) for n in aligned]
    angle_error = [_angle(aligned[n].R, by_name[n].R) for n in aligned]
    dropped = [n for n in train_names if n not in aligned]
    cameras = [aligned.get(c.name, c) for c in original.cameras if c.name not in dropped]
    model = ColmapModel(cameras=cameras, points=align.points(new.points), colors=new.colors)
    for path in model_dir.iterdir():
        path.unlink()
    write_model(model_dir, model)
    _write_split(SceneLayout(scene_dir).split_json, [n for n in train_names if n not in dropped],
                 [c.name for c in original.cameras if c.name not in train_names])
    return {"registered": len(aligned), "training_views": len(train_names), "dropped": dropped,
            "points": len(new.points), "mean_centre_error": float(np.mean(centre_error)),
            "mean_centre_error_of_extent": float(np.mean(centre_error) / extent) if extent else None,
            "mean_rotation_error_deg": float(np.mean(angle_error)), "scale": align.scale}


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    cos = (np.trace(a @ b.T) - 1) / 2
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


def _write_split(path: Path, train: list[str], test: list[str]) -> None:
    """Written by name: with views dropped, a split by position (no split.json) would move the test views."""
    path.write_text(json.dumps({"train": train, "test": test}, indent=1))
