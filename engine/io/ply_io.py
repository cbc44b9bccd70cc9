"""Gaussians (torch) to and from the standard 3DGS .ply, whose layout and numpy reader/writer live in
engine.formats.splat_ply (shared with Blender's side); this module only converts between its columns and
the engine's tensors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from engine.base.errors import InputError
from engine.formats.splat_files import read_splat_file
from engine.formats.splat_ply import (
    IDENTITY_DIM,
    property_names,
    read_classifier,
    write_classifier,
    write_vertices,
)
from engine.io.gaussians import Gaussians


def save_ply(path: Path, gaussians: Gaussians) -> None:
    """Write `gaussians` as a binary little-endian 3DGS .ply (atomically: temp file, then rename)."""
    g = {k: v.detach().cpu().float().numpy() for k, v in gaussians.items()}
    n, k = len(g["means"]), g["shN"].shape[1]
    blocks = [g["means"], np.zeros((n, 3), np.float32), g["sh0"].reshape(n, 3),
              g["shN"].transpose(0, 2, 1).reshape(n, 3 * k), g["opacities"].reshape(n, 1), g["scales"], g["quats"]]
    if "identity" in g:
        blocks.append(g["identity"].reshape(n, IDENTITY_DIM))
    data = np.concatenate(blocks, axis=1).astype(np.float32)
    names = property_names(k, "identity" in g)
    write_vertices(path, {name: data[:, i] for i, name in enumerate(names)})


def load_ply(path: Path) -> Gaussians:
    """Read a splat file (ours or any standard .ply, a compressed .ply, .splat or .spz; engine.formats.splat_files);
    identity is zero when the file has none."""
    vertex = read_splat_file(Path(path))
    fields = set(vertex.dtype.names)
    n_rest = sum(1 for f in fields if f.startswith("f_rest_"))
    n, k = len(vertex), n_rest // 3

    def stack(names: list[str]) -> torch.Tensor:
        if not names:
            return torch.zeros(n, 0)
        return torch.from_numpy(np.stack([np.asarray(vertex[f], dtype=np.float32) for f in names], axis=1))

    gaussians = {
        "means": stack(["x", "y", "z"]),
        "quats": stack([f"rot_{i}" for i in range(4)]),
        "scales": stack([f"scale_{i}" for i in range(3)]),
        "opacities": stack(["opacity"])[:, 0],
        "sh0": stack([f"f_dc_{i}" for i in range(3)])[:, None, :],
        "shN": stack([f"f_rest_{i}" for i in range(n_rest)]).reshape(n, 3, k).transpose(1, 2).contiguous(),
    }
    identity = [f"obj_dc_{i}" for i in range(IDENTITY_DIM)]
    has_identity = all(f in fields for f in identity)
    gaussians["identity"] = stack(identity) if has_identity else torch.zeros(n, IDENTITY_DIM)
    if not all(torch.isfinite(v).all() for v in gaussians.values()):
        raise InputError(f"{path} holds NaN or infinite values: the training that wrote it diverged")
    if (gaussians["quats"].norm(dim=1) < 1e-12).any():
        raise InputError(f"{path} holds Gaussians whose rotation (rot_0..3) is all zero; re-export it")
    return gaussians


def save_classifier(path: Path, classifier: torch.nn.Linear) -> None:
    write_classifier(path, classifier.weight.detach().cpu().numpy(), classifier.bias.detach().cpu().numpy())


def load_classifier(path: Path) -> torch.nn.Linear:
    weight, bias = read_classifier(Path(path))
    classifier = torch.nn.Linear(weight.shape[1], weight.shape[0])
    with torch.no_grad():
        classifier.weight.copy_(torch.from_numpy(weight))
        classifier.bias.copy_(torch.from_numpy(bias))
    return classifier
