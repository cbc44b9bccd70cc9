"""Binary mask operations shared by removal, hole masks and inpainting."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from engine.formats.cameras import Camera
from engine.io.image_io import read_png


def dilate(mask: np.ndarray, pixels: int) -> np.ndarray:
    """`mask` (H, W) grown by a disc of radius `pixels` (unchanged for 0)."""
    if pixels <= 0:
        return mask.astype(bool)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * pixels + 1, 2 * pixels + 1))
    return cv2.dilate(mask.astype(np.uint8), kernel) > 0


def read_masks(folder: Path, cameras: list[Camera], pixels: int = 0) -> dict[int, np.ndarray]:
    """Each view's mask PNG in `folder` (a stage's holes/ or masks/) as bool, grown by `pixels`."""
    return {i: dilate(read_png(folder / c.name, "mask", c.size) > 0, pixels) for i, c in enumerate(cameras)}
