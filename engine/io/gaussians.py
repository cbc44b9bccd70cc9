"""Gaussians with identities: a dict of tensors (what gsplat's strategies operate on) and the classifier.

Shapes (N Gaussians, K = (sh_degree + 1)^2 - 1 higher-order SH coefficients):
  means (N, 3) world coordinates     quats (N, 4) w, x, y, z (unnormalised)    scales (N, 3) log
  opacities (N,) logit               sh0 (N, 1, 3) SH DC                       shN (N, K, 3)
  identity (N, 16) Gaussian Grouping's identity encoding, blended like a colour
The classifier is Gaussian Grouping's per-pixel 1x1 convolution: a linear map from 16 to the class count.
"""

from __future__ import annotations

import math

import numpy as np
import torch

from engine.base.knn import knn_distances
from engine.formats.splat_ply import IDENTITY_DIM, SH_C0

PARAM_NAMES = ("means", "quats", "scales", "opacities", "sh0", "shN", "identity")

Gaussians = dict[str, torch.Tensor]


def concat(*parts: Gaussians) -> Gaussians:
    """The parts' Gaussians one after another, in order."""
    return {k: torch.cat([p[k] for p in parts]) for k in PARAM_NAMES}


def rgb_to_sh(rgb: torch.Tensor) -> torch.Tensor:
    return (rgb - 0.5) / SH_C0


def num_sh_rest(sh_degree: int) -> int:
    return (sh_degree + 1) ** 2 - 1


def init_from_points(points: np.ndarray, colors: np.ndarray, sh_degree: int = 3, init_opacity: float = 0.1,
                     seed: int = 0, sizes: np.ndarray | None = None) -> Gaussians:
    """Gaussians at the sparse points: isotropic, sized by the mean distance to the 3 nearest points (as 3DGS),
    or by `sizes` (world units, one per point) where the caller knows each point's footprint."""
    generator = torch.Generator().manual_seed(seed)
    means = torch.as_tensor(points, dtype=torch.float32)
    n = len(means)
    if sizes is None:
        dist = knn_distances(means, k=3).mean(dim=-1).clamp_min(1e-7)
    else:
        dist = torch.as_tensor(sizes, dtype=torch.float32).clamp_min(1e-7)
    quats = torch.zeros(n, 4)
    quats[:, 0] = 1.0
    return {
        "means": means,
        "quats": quats,
        "scales": torch.log(dist)[:, None].repeat(1, 3),
        "opacities": torch.full((n,), math.log(init_opacity / (1 - init_opacity))),
        "sh0": rgb_to_sh(torch.as_tensor(colors, dtype=torch.float32) / 255.0)[:, None, :],
        "shN": torch.zeros(n, num_sh_rest(sh_degree), 3),
        "identity": rgb_to_sh(torch.rand(n, IDENTITY_DIM, generator=generator)),  # as Gaussian Grouping
    }


def new_classifier(num_classes: int) -> torch.nn.Linear:
    return torch.nn.Linear(IDENTITY_DIM, num_classes)

