"""A splat trained elsewhere (the INRIA code, gsplat, nerfstudio, Postshot: a standard 3DGS .ply) plus the
COLMAP cameras it was trained on, made into a run folder without retraining, so every later stage (remove
--box, holes, inpaint, complete, Blender's import) works on it as on our own runs.

The .ply's Gaussians are kept as they are (identities zero when the file has none, until objects are
found for them); config.json names the scene and the .ply's SH degree; metrics.json holds the splat's test
PSNR/SSIM against the scene's images, which says at once whether the .ply and the cameras share a frame
(a splat exported in another frame renders nothing like the images).
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path

import torch

from engine.base.device import pick_device
from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import emit
from engine.capture.scene import load_scene
from engine.formats.layout import RunLayout
from engine.formats.splat_ply import SH_REST_COUNTS
from engine.io.gaussians import new_classifier
from engine.io.ply_io import load_ply, save_classifier, save_ply
from engine.metrics.evaluate import evaluate_views
from engine.metrics.image_metrics import psnr
from engine.train.config import TrainConfig

# dB on the test views over an empty (black) render of them: a splat in another frame renders next to nothing. Not
# a fixed PSNR: 15 dB refused a tiny CPU run in the right frame (14.5 dB), and an empty render scores 4.6 dB against
# the statue capture's photos but 11.1 against the dark skull's
MIN_GAIN_DB = 3.0


@dataclass
class ImportConfig:
    ply: str = ""  # a splat file: standard 3DGS .ply, compressed .ply, .splat or .spz
    scene: str = ""  # the COLMAP scene folder it was trained on (images/, sparse/0/)
    out: str = ""  # the new run folder
    resolution: int = 1  # the resolution the splat is checked at (1, 2, 4, 8), kept for later stages
    device: str = "auto"  # auto | cuda | cpu


def import_splat(config: ImportConfig) -> dict:
    gaussians = load_ply(Path(config.ply))
    scene_dir = Path(config.scene).resolve()
    scene = load_scene(scene_dir, config.resolution)
    degree = SH_REST_COUNTS[3 * gaussians["shN"].shape[1]]
    out = Path(config.out).resolve()
    settings = TrainConfig(scene=str(scene_dir), out=str(out), sh_degree=degree, device=config.device,
                           resolution=config.resolution)
    classifier = new_classifier(1)  # every Gaussian background until objects are found
    views = scene.test or scene.train
    metrics = evaluate_views(scene, views, gaussians, classifier, degree, pick_device(config.device))
    metrics.update(identity_miou=None, gaussians=len(gaussians["means"]), steps=settings.steps,
                   imported_from=str(Path(config.ply).resolve()))
    empty = empty_psnr(scene, views)
    if metrics["psnr"] < empty + MIN_GAIN_DB:
        raise InputError(f"{config.ply} renders at {metrics['psnr']:.1f} dB PSNR from the cameras of {scene_dir}, "
                         f"an empty scene at {empty:.1f}: they do not share a frame; export the splat in the COLMAP "
                         "model's frame")
    with atomic_output_dir(out) as tmp:
        run = RunLayout(tmp)
        save_ply(run.point_cloud, gaussians)
        save_classifier(run.classifier, classifier)
        run.config_json.write_text(json.dumps(dataclasses.asdict(settings), indent=1))
        run.objects_json.write_text(json.dumps({"objects": [dataclasses.asdict(o) for o in scene.objects]}))
        run.metrics_json.write_text(json.dumps(metrics, indent=1))
    emit("done", stage="import", out=str(out), psnr=round(metrics["psnr"], 2), gaussians=metrics["gaussians"])
    return metrics


def empty_psnr(scene, views: list[int]) -> float:
    """The mean PSNR of a black render of `views` against their images (what a splat renders where it is not)."""
    return sum(psnr(torch.zeros(scene.images[i].shape), torch.as_tensor(scene.images[i]).float() / 255.0)
               for i in views) / max(len(views), 1)
