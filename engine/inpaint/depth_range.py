"""Depth as a grey image for image inpainters, over one of the two ranges the benchmark paper compares.

global: the whole map's depth range (1st to 99th percentile of finite depths). The background keeps its
  depth, but the few grey levels left for a hole in the foreground blur its shape.
foreground: the range of the depths around the hole (a ring of about a fifth of its size), which is what
  3DGIC and the paper's finetuning use: the hole's surroundings get the full grey scale, and everything
  farther is clipped to one level (the paper's "background on one plane").
Grey is 8-bit, as the inpainters the paper feeds depth to see it.
"""

from __future__ import annotations

import numpy as np

from engine.io.masks import dilate

LEVELS = 255.0


def _ring(mask: np.ndarray) -> np.ndarray:
    ys, xs = np.nonzero(mask)
    size = max(np.ptp(ys) + 1, np.ptp(xs) + 1) if len(ys) else 1
    return dilate(mask, max(4, int(0.2 * size))) & ~mask


def depth_limits(depth: np.ndarray, mask: np.ndarray, depth_range: str) -> tuple[float, float]:
    known = np.isfinite(depth) & ~mask
    if depth_range == "foreground":
        around = known & _ring(mask)
        known = around if around.sum() >= 8 else known
    values = depth[known]
    if values.size == 0:
        return 0.0, 1.0
    near, far = np.percentile(values, [1, 99]) if depth_range == "global" else (values.min(), values.max())
    return float(near), float(max(far, near + 1e-6))


def encode_depth(depth: np.ndarray, mask: np.ndarray, depth_range: str) -> tuple[np.ndarray, float, float]:
    """(H, W) uint8 grey (near = 0), and the range it spans."""
    near, far = depth_limits(depth, mask, depth_range)
    scaled = np.clip((np.nan_to_num(depth, posinf=far) - near) / (far - near), 0.0, 1.0)
    return (scaled * LEVELS + 0.5).astype(np.uint8), near, far


def decode_depth(grey: np.ndarray, near: float, far: float) -> np.ndarray:
    return (near + grey.astype(np.float32) / LEVELS * (far - near)).astype(np.float32)
