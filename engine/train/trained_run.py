"""A finished training run read back from its folder: the stages after training all start here.

A run folder (engine.train.run) holds config.json, metrics.json, point_cloud.ply (standard 3DGS PLY with
obj_dc_* identities) and classifier.npz; the scene it was trained on is named in config.json.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from engine.base.errors import InputError
from engine.capture.scene import Scene, SceneObject, load_scene
from engine.formats.checks import read_json
from engine.formats.layout import RunLayout
from engine.io.gaussians import Gaussians
from engine.io.image_io import read_png
from engine.io.ply_io import load_classifier, load_ply
from engine.train.config import TrainConfig
from engine.train.segment_objects import identity_of, read_segment_objects


@dataclass
class TrainedRun:
    root: Path
    config: TrainConfig
    scene: Scene
    gaussians: Gaussians
    classifier: torch.nn.Linear
    sh_degree: int

    @property
    def layout(self) -> RunLayout:
        return RunLayout(self.root)


def _read_run(root: Path, scene: Path | str | None) -> tuple[TrainConfig, int, Path]:
    """The run's config, its step count and its scene folder, checked, each problem a one-line error."""
    layout = RunLayout(root)
    for path in (layout.config_json, layout.metrics_json, layout.point_cloud, layout.classifier):
        if not path.is_file():
            raise InputError(f"{path} missing: {root} is not a finished training run "
                             f"(train with `python -m engine train --scene DIR --out {root}`, or --resume it)")
    try:
        config = TrainConfig.from_saved(read_json(layout.config_json))
        steps = int(read_json(layout.metrics_json)["steps"])
    except (ValueError, TypeError, KeyError, OverflowError) as exc:
        raise InputError(f"cannot read {root}/config.json or metrics.json ({exc}); re-run training") from exc
    scene_dir = Path(scene) if scene is not None else Path(config.scene)
    if not scene_dir.is_dir():
        raise InputError(f"scene folder {scene_dir} named in {layout.config_json} is gone: pass --scene DIR")
    return config, steps, scene_dir


def load_run_scene(root: Path | str, scene: Path | str | None = None) -> Scene:
    """Only the scene of run folder `root` (`scene` overrides the folder its config.json names), for stages that
    read its files but not its Gaussians."""
    config, _, scene_dir = _read_run(Path(root), scene)
    layout = RunLayout(root)
    return _scene_with_segments(load_scene(scene_dir, config.resolution), layout, _segments(layout))


def _segments(layout: RunLayout) -> list[SceneObject] | None:
    """The objects `segment` found for this run (engine.segment.run), if it ran."""
    return read_segment_objects(layout) if layout.segments.objects_json.is_file() else None


def _scene_with_segments(scene: Scene, layout: RunLayout, objects: list[SceneObject] | None) -> Scene:
    """The scene with the segments' objects and per-view masks in place of its own, when they exist."""
    if objects is None:
        return scene
    folder = layout.segments.masks
    masks = [read_png(folder / Path(c.name).with_suffix(".png"), "mask", c.size) for c in scene.cameras]
    return dataclasses.replace(scene, objects=objects, masks=masks)


def _run_with_segments(run: TrainedRun) -> TrainedRun:
    """Identities one-hot over the segments' objects, and the classifier that reads them."""
    objects = _segments(run.layout)
    if objects is None:
        return run
    ids = np.load(run.layout.segments.ids).astype(np.int64)
    if len(ids) != len(run.gaussians["means"]):
        raise InputError(f"{run.layout.segments.ids} has {len(ids)} ids for {len(run.gaussians['means'])} "
                         "Gaussians: the run changed since; run `python -m engine segment` again")
    identity, classifier = identity_of(ids, max([o.id for o in objects], default=0))
    return dataclasses.replace(run, scene=_scene_with_segments(run.scene, run.layout, objects),
                               gaussians={**run.gaussians, "identity": identity}, classifier=classifier)


def load_splats(root: Path | str) -> tuple[Gaussians, int]:
    """Only the Gaussians of run folder `root` and the SH degree they were trained to, for a caller that holds
    the scene already (a 100-view scene takes seconds to read)."""
    root = Path(root)
    config, steps, _ = _read_run(root, None)
    return load_ply(RunLayout(root).point_cloud), config.sh_degree_at(steps)


def load_run(root: Path | str, scene: Path | str | None = None) -> TrainedRun:
    """Load run folder `root`; `scene` overrides the scene folder recorded in its config.json."""
    root = Path(root)
    config, steps, scene_dir = _read_run(root, scene)
    run = TrainedRun(root=root, config=config, scene=load_scene(scene_dir, config.resolution),
                     gaussians=load_ply(RunLayout(root).point_cloud),
                     classifier=load_classifier(RunLayout(root).classifier),
                     sh_degree=config.sh_degree_at(steps))
    return _run_with_segments(run)
