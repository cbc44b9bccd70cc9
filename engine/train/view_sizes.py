"""The training views on the device at each size a coarse-to-fine schedule uses (TrainConfig.coarse_factor).

Reduced the way a downscaled scene folder is (engine.io.downscale): cameras through `scaled_camera`, images by
area, identity labels by nearest neighbour (ids must not blend). Made once when training starts: a quarter
and a sixteenth of the full-size images add 31% to their memory (27 MB at 640x480 and 90 views).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
import torch

from engine.io.downscale import scaled_camera
from engine.io.scene import Scene
from engine.render.rasterize import CameraTensors


@dataclass
class ViewSize:
    """The training views at 1/factor of the scene's size: cameras, uint8 images and labels (or None)."""

    cameras: dict[int, CameraTensors]
    images: dict[int, torch.Tensor]
    labels: dict[int, torch.Tensor] | None


def view_size(scene: Scene, views: list[int], factor: int, device: torch.device) -> ViewSize:
    cameras = {i: scaled_camera(scene.cameras[i], factor) for i in views}

    def reduced(image: np.ndarray, i: int, interpolation: int) -> np.ndarray:
        size = (cameras[i].width, cameras[i].height)
        return image if factor == 1 else np.ascontiguousarray(cv2.resize(image, size, interpolation=interpolation))

    images = {i: torch.as_tensor(reduced(scene.images[i], i, cv2.INTER_AREA), device=device) for i in views}
    labels = None
    if scene.masks is not None:
        labels = {i: torch.as_tensor(reduced(scene.masks[i], i, cv2.INTER_NEAREST), device=device).long()
                  for i in views}
    return ViewSize({i: CameraTensors.from_camera(c, device) for i, c in cameras.items()}, images, labels)


def schedule_factors(coarse_factor: int) -> list[int]:
    """Every factor a schedule starting at 1/coarse_factor passes through: 4 -> [4, 2, 1]."""
    return [coarse_factor >> k for k in range(max(coarse_factor, 1).bit_length())]
