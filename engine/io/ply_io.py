"""The standard 3DGS .ply layout, plus Gaussian Grouping's identity as obj_dc_0..15.

Properties, in the order the reference code writes them:
  x y z nx ny nz f_dc_0..2 f_rest_0..(3K-1) opacity scale_0..2 rot_0..3 [obj_dc_0..15]
f_rest is channel-major (all K coefficients of red, then green, then blue), rot is w, x, y, z; opacity is
a logit and scales are logs, exactly as stored in training. Ordinary splat viewers ignore obj_dc_*.
The classifier goes beside the .ply as classifier.npz (weight (C, 16), bias (C,)): numpy only, so that
Blender-side code can group Gaussians by identity without torch.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch
from plyfile import PlyData, PlyElement

from engine.base.errors import InputError
from engine.io.gaussians import IDENTITY_DIM, Gaussians

SH_REST_COUNTS = {0: 0, 9: 1, 24: 2, 45: 3}  # number of f_rest properties -> SH degree


def _property_names(k: int, with_identity: bool) -> list[str]:
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"]
    names += [f"f_rest_{i}" for i in range(3 * k)]
    names += ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    if with_identity:
        names += [f"obj_dc_{i}" for i in range(IDENTITY_DIM)]
    return names


def save_ply(path: Path, gaussians: Gaussians) -> None:
    """Write `gaussians` as a binary little-endian 3DGS .ply (atomically: temp file, then rename)."""
    g = {k: v.detach().cpu().float().numpy() for k, v in gaussians.items()}
    n, k = len(g["means"]), g["shN"].shape[1]
    columns = [g["means"], np.zeros((n, 3), np.float32), g["sh0"].reshape(n, 3),
               g["shN"].transpose(0, 2, 1).reshape(n, 3 * k), g["opacities"].reshape(n, 1), g["scales"], g["quats"]]
    if "identity" in g:
        columns.append(g["identity"].reshape(n, IDENTITY_DIM))
    data = np.concatenate(columns, axis=1).astype(np.float32)
    names = _property_names(k, "identity" in g)
    vertex = np.empty(n, dtype=[(name, "f4") for name in names])
    for i, name in enumerate(names):
        vertex[name] = data[:, i]
    tmp = Path(path).with_suffix(".ply.tmp")
    PlyData([PlyElement.describe(vertex, "vertex")]).write(str(tmp))
    tmp.replace(path)


def load_ply(path: Path) -> Gaussians:
    """Read a 3DGS .ply (ours or any standard one); identity is zero when the file has none."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"missing Gaussian file {path}: train a scene first or pass the right --run")
    try:
        ply = PlyData.read(str(path))
        vertex = ply["vertex"].data
    except Exception as exc:  # plyfile raises many types on truncated or foreign files
        raise InputError(f"cannot read {path} as a 3DGS .ply ({type(exc).__name__}: {exc}); "
                         "the file is truncated or not a splat file") from exc
    fields = set(vertex.dtype.names or ())
    n_rest = sum(1 for f in fields if f.startswith("f_rest_"))
    missing = [f for f in _property_names(0, False) if f not in fields and f not in ("nx", "ny", "nz")]
    if missing or n_rest not in SH_REST_COUNTS:
        raise InputError(f"{path} is not a 3DGS .ply: missing {missing or f'a valid f_rest count ({n_rest})'}")
    k = n_rest // 3

    n = len(vertex)

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
    return gaussians


def save_classifier(path: Path, classifier: torch.nn.Linear) -> None:
    tmp = Path(path).with_suffix(".tmp.npz")
    np.savez(tmp, weight=classifier.weight.detach().cpu().numpy(), bias=classifier.bias.detach().cpu().numpy())
    tmp.replace(path)


def load_classifier(path: Path) -> torch.nn.Linear:
    path = Path(path)
    try:
        data = np.load(path)
        weight, bias = data["weight"], data["bias"]
    except (OSError, KeyError, ValueError) as exc:
        raise InputError(f"cannot read classifier {path} ({exc}); re-run training") from exc
    classifier = torch.nn.Linear(weight.shape[1], weight.shape[0])
    with torch.no_grad():
        classifier.weight.copy_(torch.from_numpy(weight))
        classifier.bias.copy_(torch.from_numpy(bias))
    return classifier
