"""`clean`: delete stray Gaussians at once, as splat editors do, without a removal's relighting and renders.

A Gaussian goes when it is fainter than `min_opacity`, larger than `max_size` (its largest standard deviation, world
units), farther than `max_distance` from the subject (the centre of object_1 when `segment` found objects, else the
point the cameras look at), outside the `crop` box, or, with `around_cameras`, when its 1-sigma core
(camera_clearance.SIGMAS) holds one of the scene's cameras (engine.train.camera_clearance: drawn flat over whole
views; training empties these itself, a splat trained elsewhere and imported may hold them). The result is a new run
folder: the kept Gaussians in point_cloud.ply (every field as it was), the run's config, classifier and objects, and
its segments with their per-Gaussian ids cut to match (their per-view masks kept: they were rendered before the
clean-up, and only the floaters changed), so every later stage takes it as it takes the original.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import torch

from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import emit
from engine.formats.colmap_files import find_model_dir
from engine.formats.layout import RunLayout
from engine.formats.splat_files import read_splat_file
from engine.formats.splat_ply import write_vertices
from engine.geometry.scene_geometry import camera_frame
from engine.io.colmap_model import read_model
from engine.train.camera_clearance import centres_of, holding_cameras


@dataclass
class CleanConfig:
    run: str = ""  # the training run (or a completion's RUN/complete/<Method>/run)
    out: str = ""  # the new run folder (default RUN-clean)
    min_opacity: float = 0.0  # delete Gaussians fainter than this (0-1)
    max_size: float = 0.0  # delete those whose largest standard deviation exceeds this, world units (0: off)
    max_distance: float = 0.0  # delete those farther than this from the subject, world units (0: off)
    crop: list[float] = field(default_factory=list)  # x0 y0 z0 x1 y1 z1: delete what lies outside
    around_cameras: bool = False  # delete those whose 1-sigma core holds one of the scene's cameras

    def __post_init__(self) -> None:
        self.crop = [float(v) for v in self.crop]  # saved in clean.json


def deletions(vertices: np.ndarray, means: np.ndarray, config: CleanConfig, subject: np.ndarray | None,
              cameras: torch.Tensor | None = None) -> dict[str, np.ndarray]:
    """Per rule, the (N,) bool of the Gaussians (`vertices`, their centres `means`) it deletes; `cameras` (C, 3)
    the scene's camera centres, which `around_cameras` needs."""
    rules = {}
    if config.min_opacity > 0:
        rules["opacity"] = 1 / (1 + np.exp(-vertices["opacity"].astype(np.float64))) < config.min_opacity
    if config.max_size > 0:
        rules["size"] = np.exp(np.stack([vertices[f"scale_{i}"] for i in range(3)], 1).max(1)) > config.max_size
    if config.max_distance > 0:
        if subject is None:
            raise InputError("--max-distance needs the subject's place: the run names no scene with cameras")
        rules["distance"] = np.linalg.norm(means - subject, axis=1) > config.max_distance
    if config.crop:
        if len(config.crop) != 6:
            raise InputError(f"--crop needs 6 numbers x0 y0 z0 x1 y1 z1, got {len(config.crop)}")
        lo, hi = np.minimum(config.crop[:3], config.crop[3:]), np.maximum(config.crop[:3], config.crop[3:])
        rules["crop"] = ~np.all((means >= lo) & (means <= hi), axis=1)
    if config.around_cameras:
        if cameras is None:
            raise InputError("--around-cameras needs the cameras: the run names no scene with a COLMAP model")
        rules["around_cameras"] = holding_cameras(
            torch.as_tensor(means, dtype=torch.float32),
            torch.as_tensor(np.stack([vertices[f"rot_{i}"] for i in range(4)], 1), dtype=torch.float32),
            torch.as_tensor(np.stack([vertices[f"scale_{i}"] for i in range(3)], 1), dtype=torch.float32),
            cameras).numpy()
    if not rules:
        raise InputError("nothing to clean: give --min-opacity, --max-size, --max-distance, --crop or "
                         "--around-cameras")
    return rules


def run_clean(config: CleanConfig) -> dict:
    run = RunLayout(config.run)
    if not run.config_json.is_file():
        raise InputError(f"{run.root} is not a run folder (no {run.config_json.name}): give a trained run")
    out = RunLayout(config.out or str(run.root) + "-clean")
    vertices = read_splat_file(run.point_cloud)
    means = np.stack([vertices[c] for c in ("x", "y", "z")], 1).astype(np.float64)
    rules = deletions(vertices, means, config, _subject(run, means) if config.max_distance > 0 else None,
                      _camera_centres(run) if config.around_cameras else None)
    gone = np.logical_or.reduce(list(rules.values()))
    if gone.all():
        raise InputError(f"these limits delete all {len(gone)} Gaussians of {run.point_cloud}: loosen them")
    with atomic_output_dir(out.root) as tmp:
        target = RunLayout(tmp)
        write_vertices(target.point_cloud, {c: vertices[c][~gone] for c in vertices.dtype.names})
        for source, copy in ((run.config_json, target.config_json), (run.classifier, target.classifier),
                             (run.objects_json, target.objects_json)):
            if source.is_file():
                shutil.copy(source, copy)
        if run.segments.ids.is_file():
            shutil.copytree(run.segments.root, target.segments.root)
            np.save(target.segments.ids, np.load(run.segments.ids)[~gone])
        report = {"config": asdict(config), "before": int(len(gone)), "deleted": int(gone.sum()),
                  "by_rule": {k: int(v.sum()) for k, v in rules.items()}}
        (tmp / "clean.json").write_text(json.dumps(report, indent=1))
    emit("done", stage="clean", out=str(out.root), deleted=report["deleted"], kept=int((~gone).sum()))
    return report


def _subject(run: RunLayout, means: np.ndarray) -> np.ndarray:
    """object_1's median position where `segment` found objects, else the point the cameras look at."""
    if run.segments.ids.is_file():
        ids = np.load(run.segments.ids)
        if len(ids) == len(means) and (ids == 1).any():
            return np.median(means[ids == 1], axis=0)
    return camera_frame(_scene_cameras(run, "--max-distance needs its cameras or found objects")).center


def _camera_centres(run: RunLayout) -> torch.Tensor:
    """(C, 3) the centres of the cameras of the run's scene."""
    return centres_of(_scene_cameras(run, "--around-cameras needs its cameras"))


def _scene_cameras(run: RunLayout, why: str) -> list:
    """The cameras of the scene the run's config.json names."""
    scene = json.loads(run.config_json.read_text()).get("scene")
    if not scene:
        raise InputError(f"{run.config_json} names no scene: {why}")
    return read_model(find_model_dir(Path(scene))).cameras
