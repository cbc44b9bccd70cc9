""".splat, the layout antimatter15's WebGL viewer introduced and most web viewers read: 32 bytes a Gaussian, no
header, no spherical-harmonic bands beyond the colour.

Per Gaussian, little-endian: position float32 x3; scale float32 x3 (standard deviations, exp of the .ply's log
scales); colour uint8 RGBA (0.5 + SH_C0 * f_dc and the sigmoid of the opacity, times 255); rotation uint8 x4,
w x y z of the unit quaternion as round(128 q + 128), clipped to 0..255. Viewers draw the Gaussians in file order
and sort them themselves, so none is written here.

Columns in and out are the INRIA .ply's (engine.formats.splat_ply): x y z f_dc_0..2 opacity scale_0..2 rot_0..3.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..base.errors import InputError
from .splat_ply import SH_C0

RECORD = np.dtype([("position", "<f4", 3), ("scale", "<f4", 3), ("rgba", "u1", 4), ("rotation", "u1", 4)])


def encode(columns: dict[str, np.ndarray]) -> bytes:
    """The .splat bytes of Gaussians given as INRIA .ply columns."""
    n = len(columns["x"])
    record = np.zeros(n, RECORD)
    record["position"] = np.stack([columns[k] for k in ("x", "y", "z")], 1)
    record["scale"] = np.exp(np.stack([columns[f"scale_{i}"] for i in range(3)], 1))
    rgb = 0.5 + SH_C0 * np.stack([columns[f"f_dc_{i}"] for i in range(3)], 1)
    alpha = 1.0 / (1.0 + np.exp(-columns["opacity"].astype(np.float64)))
    record["rgba"] = np.clip(np.round(np.concatenate([rgb, alpha[:, None]], 1) * 255), 0, 255)
    quat = np.stack([columns[f"rot_{i}"] for i in range(4)], 1).astype(np.float64)
    quat /= np.maximum(np.linalg.norm(quat, axis=1, keepdims=True), 1e-12)
    record["rotation"] = np.clip(np.round(quat * 128 + 128), 0, 255)
    return record.tobytes()


def decode(data: bytes, path: Path) -> dict[str, np.ndarray]:
    """INRIA .ply columns (float32) of a .splat file's bytes."""
    if len(data) % RECORD.itemsize:
        raise InputError(f"{path} holds {len(data)} bytes, not a whole number of 32-byte .splat records: is it a "
                         ".splat file?")
    record = np.frombuffer(data, RECORD)
    rgba = record["rgba"].astype(np.float64) / 255
    alpha = np.clip(rgba[:, 3], 0.5 / 255, 1 - 0.5 / 255)
    quat = (record["rotation"].astype(np.float64) - 128) / 128
    quat /= np.maximum(np.linalg.norm(quat, axis=1, keepdims=True), 1e-12)
    scale = np.log(np.maximum(record["scale"].astype(np.float64), 1e-30))
    columns = {k: record["position"][:, i] for i, k in enumerate(("x", "y", "z"))}
    columns |= {f"f_dc_{i}": (rgba[:, i] - 0.5) / SH_C0 for i in range(3)}
    columns["opacity"] = np.log(alpha / (1 - alpha))
    columns |= {f"scale_{i}": scale[:, i] for i in range(3)}
    columns |= {f"rot_{i}": quat[:, i] for i in range(4)}
    return {k: np.asarray(v, np.float32) for k, v in columns.items()}
