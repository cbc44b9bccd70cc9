"""Hand-built Gaussians for tests with a worked-out answer: round, axis-aligned, one colour each."""

from __future__ import annotations

import math

import numpy as np
import torch

from engine.formats.splat_ply import SH_C0

SPACING = 0.04  # a grid's step, and the Gaussians' scale on it


def gaussians(means: np.ndarray, colors: np.ndarray, opacity: float = 0.95, scale: float = SPACING) -> dict:
    """(N, 3) means and (N, 3) RGB colours in [0, 1] as the engine's Gaussian tensors (SH degree 0)."""
    n = len(means)
    return {"means": torch.as_tensor(means, dtype=torch.float32),
            "quats": torch.tensor([[1.0, 0.0, 0.0, 0.0]]).repeat(n, 1),
            "scales": torch.full((n, 3), math.log(scale)),
            "opacities": torch.full((n,), math.log(opacity / (1 - opacity))),
            "sh0": torch.as_tensor((colors - 0.5) / SH_C0, dtype=torch.float32)[:, None],
            "shN": torch.zeros(n, 15, 3), "identity": torch.zeros(n, 16)}
