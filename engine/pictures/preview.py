"""Pictures people look at: a contact sheet of a scene's views and their ground truth."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from engine.capture.scene import Scene
from engine.io.image_io import write_png

PALETTE = np.array([[0, 0, 0]] + [[(37 * i) % 256, (97 * i + 80) % 256, (173 * i + 40) % 256]
                                  for i in range(1, 256)], dtype=np.uint8)


def colorize_ids(ids: np.ndarray) -> np.ndarray:
    """(H, W) instance ids to a distinct colour each (0 stays black)."""
    return PALETTE[ids]


def colorize_depth(depth: np.ndarray, near: float | None = None, far: float | None = None) -> np.ndarray:
    """(H, W) depth to a turbo-coloured RGB image; inf (no surface) is black."""
    finite = np.isfinite(depth)
    if not finite.any():
        return np.zeros((*depth.shape, 3), np.uint8)
    near = np.percentile(depth[finite], 1) if near is None else near
    far = np.percentile(depth[finite], 99) if far is None else far
    scaled = np.clip((depth - near) / max(far - near, 1e-9), 0, 1)
    rgb = cv2.cvtColor(cv2.applyColorMap((np.nan_to_num(scaled) * 255).astype(np.uint8), cv2.COLORMAP_TURBO),
                       cv2.COLOR_BGR2RGB)
    rgb[~finite] = 0
    return rgb


def label(image: np.ndarray, text: str) -> np.ndarray:
    """A copy of `image` with `text` in its top-left corner."""
    out = image.copy()
    scale = max(out.shape[1] / 400, 0.35)
    thick = max(1, round(scale))  # strokes as wide as the letters are large
    (_, height), _ = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, scale, thick + 2)
    origin = (4, height + 5)  # the text's baseline: its tallest letters end 5 px below the top, not above it
    cv2.putText(out, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), thick + 2, cv2.LINE_AA)
    cv2.putText(out, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), thick, cv2.LINE_AA)
    return out


def overlay(image: np.ndarray, mask: np.ndarray, color=(255, 0, 255)) -> np.ndarray:
    """`image` with `mask` (H, W) bool tinted in `color`."""
    out = image.copy()
    out[mask] = (0.4 * out[mask] + 0.6 * np.array(color)).astype(np.uint8)
    return out


def write_scene_preview(scene: Scene, path: Path, rows: int = 3) -> Path:
    """One row per view (test views first): image, gt, masks, depth, hole over gt."""
    views = (scene.test + scene.train)[:rows]
    lines = []
    for i in views:
        image = scene.images[i]
        tiles = [label(image, f"{scene.names[i]} image")]
        if i in scene.gt_images:
            tiles.append(label(scene.gt_images[i], "gt"))
        if scene.masks is not None:
            tiles.append(label(colorize_ids(scene.masks[i]), "masks"))
        if scene.depths is not None:
            tiles.append(label(colorize_depth(scene.depths[i]), "depth"))
        if i in scene.holes:
            tiles.append(label(overlay(scene.gt_images.get(i, image), scene.holes[i]), "hole"))
        lines.append(np.concatenate(tiles, axis=1))
    width = max(line.shape[1] for line in lines)
    sheet = np.concatenate([np.pad(line, ((0, 0), (0, width - line.shape[1]), (0, 0))) for line in lines], axis=0)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_png(path, sheet)
    return path
