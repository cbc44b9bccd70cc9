"""The scene folder a completion trains on: the original scene with the inpainted training images.

sparse/, split.json, scene.json, gt/, holes/ and unseen/ as they were; images/ the training views: the inpainted
image (inside `keep` when a method gives regions, the input image elsewhere), the test views the ground
truth when the scene has it (so the training run's own test PSNR means something; they are never trained
on); masks/ with the removed object's id turned into background.
"""

from __future__ import annotations

import dataclasses
import json
import shutil
from pathlib import Path

import numpy as np

from engine.capture.scene import Scene
from engine.formats.layout import InpaintedLayout, SceneLayout
from engine.io.image_io import read_png, write_png


def write_training_scene(scene: Scene, inpainted: InpaintedLayout, target_id: int | None, out: SceneLayout,
                         keep: dict[int, np.ndarray] | None = None) -> SceneLayout:
    source = SceneLayout(scene.root)
    shutil.copytree(source.sparse, out.sparse)
    for path, copy in ((source.split_json, out.split_json), (source.scene_json, out.scene_json)):
        if path.is_file():
            shutil.copy2(path, copy)
    for folder, copy in ((source.gt, out.gt), (source.holes, out.holes), (source.unseen, out.unseen)):
        if folder.is_dir():
            shutil.copytree(folder, copy)
    for i, camera in enumerate(scene.cameras):
        if i in scene.test:
            image = scene.gt_images.get(i, scene.images[i])
        else:
            image = read_png(inpainted.images / camera.name, size=camera.size)
            if keep is not None:
                image = np.where(keep[i][..., None], image, scene.images[i])
        write_png(out.images / camera.name, image)
    if scene.masks is not None:
        for camera, mask in zip(scene.cameras, scene.masks, strict=True):
            write_png(out.masks / Path(camera.name).with_suffix(".png"),
                      np.where(mask == target_id, 0, mask).astype(np.uint8))
        objects = [dataclasses.asdict(o) for o in scene.objects if o.id != target_id]
        out.objects_json.write_text(json.dumps(objects, indent=1))
    return out
