"""Render a set of Gaussians into numpy pictures for the stages that write files (removal, holes, sheets),
and into a folder of PNGs from a cameras.json (turntable frames)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from engine.base.device import pick_device
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import Progress, emit
from engine.formats.cameras import Camera, read_cameras_json
from engine.formats.splat_ply import SH_REST_COUNTS
from engine.io.gaussians import Gaussians
from engine.io.image_io import write_png
from engine.io.ply_io import load_ply
from engine.render.rasterize import CameraTensors, default_backend, render
from engine.render.surface_depth import surface_depth


@dataclass
class ViewPicture:
    rgb: np.ndarray  # (H, W, 3) uint8
    depth: np.ndarray | None  # (H, W) float32 z-depth of the surface shown (engine.render.surface_depth), inf
    # where alpha < 1/2; None when not asked for
    labels: np.ndarray | None  # (H, W) uint8 argmax class, with a classifier
    alpha: np.ndarray | None = None  # (H, W) float32 blended opacity (where the surface shown is whole), when asked


@torch.no_grad()
def render_pictures(gaussians: Gaussians, cameras: list[Camera], sh_degree: int, device: torch.device,
                    classifier: torch.nn.Linear | None = None, depth: bool = True,
                    alpha: bool = False) -> Iterator[ViewPicture]:
    """One ViewPicture per camera, in order; the Gaussians are moved to `device` once. The surface depth
    costs one more rasterization per view: `depth=False` skips it. `alpha=True` keeps the blended opacity too (a
    float a pixel: a capture's views in removal would hold hundreds of MB of it unasked)."""
    on_device = {k: v.to(device) for k, v in gaussians.items()}
    classifier = classifier.to(device) if classifier is not None else None
    for camera in cameras:
        tensors = CameraTensors.from_camera(camera, device)
        out = render(on_device, tensors, sh_degree, classifier=classifier, depth=False)
        rgb = (out.rgb.clamp(0, 1) * 255 + 0.5).to(torch.uint8)
        labels = out.logits.argmax(-1).to(torch.uint8).cpu().numpy() if out.logits is not None else None
        surface = surface_depth(on_device, tensors, default_backend(device))[0].float().cpu().numpy() if depth else None
        opacity = out.alpha.float().cpu().numpy() if alpha else None
        yield ViewPicture(rgb=rgb.cpu().numpy(), depth=surface, labels=labels, alpha=opacity)


def render_depths(gaussians: Gaussians, cameras: list[Camera], sh_degree: int, device: torch.device, stage: str
                  ) -> list[np.ndarray]:
    """The z-depth (inf where nothing is rendered) of each camera's view, with progress as `stage`: what
    the hole masks and the lifting of user masks test visibility against."""
    progress = Progress(stage, len(cameras))
    depths = []
    for k, picture in enumerate(render_pictures(gaussians, cameras, sh_degree, device)):
        depths.append(picture.depth)
        progress.update(k + 1)
    progress.close()
    return depths


def render_to_folder(ply: Path, cameras_json: Path, out: Path, device: str = "auto") -> Path:
    """Render a .ply from every camera of a cameras.json into out/<camera name> (PNG), written atomically:
    the turntable's frames and any other camera path a user brings."""
    gaussians, cameras = load_ply(ply), read_cameras_json(cameras_json)
    sh_degree = SH_REST_COUNTS[3 * gaussians["shN"].shape[1]]  # load_ply checked the count
    with atomic_output_dir(out) as tmp:
        progress = Progress("render", len(cameras))
        for k, picture in enumerate(render_pictures(gaussians, cameras, sh_degree, pick_device(device))):
            write_png(tmp / cameras[k].name, picture.rgb)
            progress.update(k + 1)
        progress.close()
    emit("done", stage="render", out=str(out), views=len(cameras))
    return Path(out)
