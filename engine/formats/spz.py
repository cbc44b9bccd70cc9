""".spz, Niantic's compressed splat format (version 3, as its reference library writes it; versions 2 and 3 read),
written from its published specification (github.com/nianticlabs/spz, README "File Format").

A gzip stream of a 16-byte header (uint32 magic 0x5053474e, version, count; uint8 SH degree, fractional bits,
flags, reserved) and the arrays, attribute by attribute: positions as 24-bit signed fixed point (12 fractional
bits), alphas uint8 (sigmoid x 255), colours uint8 (f_dc x 0.15 x 255 + 127.5), scales uint8 ((log + 10) x 16),
rotations (v3: the smallest three components of the unit quaternion, x y z w order, 10 bits each with a sign
bit, and the largest's index in 2 bits; v2: x y z as uint8 with w >= 0 implied), then the SH bands, channel
fastest within each coefficient, as uint8 round(128 c) + 128 (coefficients assumed in [-1, 1]).

.spz stores right-up-back axes; a 3DGS .ply is right-down-forward (COLMAP's). Writing converts as the reference
library does when told the source is RDF: y and z negated, so a quaternion's y and z and the SH coefficients odd in
y + z change sign; reading converts back. Columns in and out are the INRIA .ply's (engine.formats.splat_ply).
"""

from __future__ import annotations

import gzip
import struct
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from .splat_ply import SH_REST_COUNTS

MAGIC = 0x5053474E
VERSION = 3
FRACTIONAL_BITS = 12
COLOR_SCALE = 0.15  # the reference's: base colours a little outside [0, 1] survive
# sign of each SH coefficient (bands 1-3, basis order of the 3DGS code) under y -> -y, z -> -z
SH_FLIP = np.array([-1, -1, 1, -1, 1, 1, -1, 1, -1, 1, -1, -1, 1, -1, 1], np.float64)
SQRT1_2 = np.sqrt(0.5)


def encode(columns: dict[str, np.ndarray], sh_degree: int) -> bytes:
    """The .spz bytes (gzipped) of Gaussians given as INRIA .ply columns, with `sh_degree` bands of colour."""
    n, k = len(columns["x"]), (sh_degree + 1) ** 2 - 1
    flip = np.array([1.0, -1.0, -1.0])
    position = np.stack([columns[c] for c in ("x", "y", "z")], 1).astype(np.float64) * flip
    fixed = np.round(position * (1 << FRACTIONAL_BITS)).astype(np.int64)
    if np.abs(fixed).max(initial=0) >= 1 << 23:
        raise InputError(f"positions reach {np.abs(position).max():.0f} units, beyond .spz's 24-bit fixed point "
                         f"(+-{(1 << 23) / (1 << FRACTIONAL_BITS):.0f}): export as .ply")
    positions = np.stack([(fixed >> s) & 0xFF for s in (0, 8, 16)], -1).astype(np.uint8)
    alpha = 1.0 / (1.0 + np.exp(-columns["opacity"].astype(np.float64)))
    colors = np.stack([columns[f"f_dc_{i}"] for i in range(3)], 1) * (COLOR_SCALE * 255) + 127.5
    scales = (np.stack([columns[f"scale_{i}"] for i in range(3)], 1) + 10.0) * 16.0
    wxyz = np.stack([columns[f"rot_{i}"] for i in range(4)], 1).astype(np.float64)
    xyzw = np.concatenate([wxyz[:, 1:], wxyz[:, :1]], 1) * [1.0, -1.0, -1.0, 1.0]
    body = [positions, _u8(alpha * 255), _u8(colors), _u8(scales), _smallest_three(xyzw)]
    if k:
        rest = np.stack([columns[f"f_rest_{i}"] for i in range(3 * k)], 1).reshape(n, 3, k)  # channel-major
        coeffs = rest.transpose(0, 2, 1) * SH_FLIP[:k, None]  # (n, coefficient, channel): channel fastest
        body.append(_u8(coeffs * 128 + 128))
    header = struct.pack("<IIIBBBB", MAGIC, VERSION, n, sh_degree, FRACTIONAL_BITS, 0, 0)
    return gzip.compress(header + b"".join(a.tobytes() for a in body), compresslevel=6)


def decode(data: bytes, path: Path) -> dict[str, np.ndarray]:
    """INRIA .ply columns (float32) of an .spz file's bytes."""
    try:
        raw = gzip.decompress(data)
    except (OSError, EOFError) as exc:
        raise InputError(f"{path} is not gzip data ({exc}): is it an .spz file?") from exc
    if len(raw) < 16:
        raise InputError(f"{path} is too short for an .spz header")
    magic, version, n, degree, bits, flags, _ = struct.unpack_from("<IIIBBBB", raw)
    if magic != MAGIC or version not in (2, 3) or degree > 3:
        raise InputError(f"{path}: not an .spz file this reader takes (magic {magic:#x}, version {version}, SH "
                         f"degree {degree}; versions 2-3, degree 0-3)")
    if flags & 0x2:
        raise InputError(f"{path} carries .spz extensions, which this reader does not take: save it without them")
    k = (degree + 1) ** 2 - 1
    sizes = [9 * n, n, 3 * n, 3 * n, (4 if version == 3 else 3) * n, 3 * k * n]
    if len(raw) != 16 + sum(sizes):
        raise InputError(f"{path} holds {len(raw) - 16} bytes of Gaussians where its header says {sum(sizes)}")
    parts, offset = [], 16
    for size in sizes:
        parts.append(np.frombuffer(raw, np.uint8, size, offset))
        offset += size
    fixed = parts[0].reshape(n, 3, 3).astype(np.int64)
    fixed = fixed[..., 0] | fixed[..., 1] << 8 | fixed[..., 2] << 16
    fixed = np.where(fixed & 0x800000, fixed - (1 << 24), fixed)
    position = fixed / float(1 << bits) * [1.0, -1.0, -1.0]
    alpha = np.clip(parts[1] / 255.0, 0.5 / 255, 1 - 0.5 / 255)
    colors = (parts[2].reshape(n, 3) / 255.0 - 0.5) / COLOR_SCALE
    scales = parts[3].reshape(n, 3) / 16.0 - 10.0
    rotation = parts[4].reshape(n, -1)
    xyzw = (_from_smallest_three(rotation) if version == 3 else _from_first_three(rotation)) * [1.0, -1.0, -1.0, 1.0]
    columns = {c: position[:, i] for i, c in enumerate(("x", "y", "z"))}
    columns |= {f"f_dc_{i}": colors[:, i] for i in range(3)}
    if k:
        coeffs = (parts[5].reshape(n, k, 3) - 128.0) / 128.0 * SH_FLIP[:k, None]
        rest = coeffs.transpose(0, 2, 1).reshape(n, 3 * k)
        columns |= {f"f_rest_{i}": rest[:, i] for i in range(3 * k)}
    columns["opacity"] = np.log(alpha / (1 - alpha))
    columns |= {f"scale_{i}": scales[:, i] for i in range(3)}
    columns |= {f"rot_{i}": xyzw[:, (3, 0, 1, 2)[i]] for i in range(4)}
    return {c: np.asarray(v, np.float32) for c, v in columns.items()}


def sh_degree_of(columns: dict[str, np.ndarray]) -> int:
    """The SH degree the columns hold (their f_rest count, as in a .ply)."""
    rest = sum(1 for c in columns if c.startswith("f_rest_"))
    if rest not in SH_REST_COUNTS:
        raise InputError(f"{rest} f_rest columns are no SH degree (0, 9, 24 or 45)")
    return SH_REST_COUNTS[rest]


def _u8(values: np.ndarray) -> np.ndarray:
    return np.clip(np.round(values), 0, 255).astype(np.uint8)


def _smallest_three(xyzw: np.ndarray) -> np.ndarray:
    """(N, 4) uint8: the largest component's index in the top 2 bits of a little-endian uint32, then each other
    component (in order) as a sign bit and 9 bits of |q| / sqrt(1/2), the largest made positive."""
    q = xyzw / np.maximum(np.linalg.norm(xyzw, axis=1, keepdims=True), 1e-12)
    largest = np.abs(q).argmax(1)
    q = np.where(q[np.arange(len(q)), largest][:, None] < 0, -q, q)
    packed = largest.astype(np.uint64)
    for i in range(4):
        magnitude = np.floor(511 * np.abs(q[:, i]) / SQRT1_2 + 0.5).astype(np.uint64)
        word = (q[:, i] < 0).astype(np.uint64) << 9 | np.minimum(magnitude, 511)
        packed = np.where(largest == i, packed, packed << 10 | word)
    return packed.astype("<u4").view(np.uint8).reshape(-1, 4)


def _from_smallest_three(data: np.ndarray) -> np.ndarray:
    packed = data.copy().view("<u4")[:, 0].astype(np.int64)
    largest = packed >> 30
    q = np.zeros((len(packed), 4))
    for i in (3, 2, 1, 0):  # the last component written sits in the lowest bits
        take = largest != i
        word = packed & 0x3FF
        value = SQRT1_2 * (word & 0x1FF) / 511.0 * np.where(word >> 9 & 1, -1.0, 1.0)
        q[take, i] = value[take]
        packed = np.where(take, packed >> 10, packed)
    q[np.arange(len(q)), largest] = np.sqrt(np.maximum(0.0, 1.0 - (q ** 2).sum(1)))
    return q


def _from_first_three(data: np.ndarray) -> np.ndarray:
    xyz = data / 127.5 - 1.0
    return np.concatenate([xyz, np.sqrt(np.maximum(0.0, 1.0 - (xyz ** 2).sum(1)))[:, None]], 1)
