"""The compressed .ply SuperSplat and PlayCanvas's splat-transform write: 16 bytes a Gaussian plus SH bytes,
written from the format as splat-transform's writer defines it (`write-compressed-ply.ts`, `compressed-chunk.ts`).

Elements: `chunk` (one per 256 Gaussians, float min_x min_y min_z max_x max_y max_z, min_scale_x.. max_scale_z,
min_r min_g min_b max_r max_g max_b), `vertex` (uint packed_position, packed_rotation, packed_scale,
packed_color) and, with SH bands, `sh` (uchar f_rest_0.., the .ply's channel-major order). Within its chunk a
Gaussian's position and log scale are 11-10-11-bit fractions of the chunk's range, x in the top bits; its colour
(0.5 + SH_C0 f_dc) is 8 bits a channel of the chunk's range and its alpha (the opacity's sigmoid) 8 bits, r in
the top byte; its quaternion (rot_0..3, normalised, the largest made positive) keeps the largest component's
index in the top 2 bits and the other three as 10-bit (q sqrt(2)/2 + 0.5); an SH coefficient is
trunc((c / 8 + 0.5) x 256) clipped to 255. Gaussians are written in their order (splat-transform sorts them in
Morton order first, which only makes chunks tighter).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..base.errors import InputError
from .splat_ply import PLY_TYPES, SH_C0

CHUNK = 256
CHUNK_FIELDS = ["min_x", "min_y", "min_z", "max_x", "max_y", "max_z", "min_scale_x", "min_scale_y", "min_scale_z",
                "max_scale_x", "max_scale_y", "max_scale_z", "min_r", "min_g", "min_b", "max_r", "max_g", "max_b"]
VERTEX_FIELDS = ["packed_position", "packed_rotation", "packed_scale", "packed_color"]


def encode(columns: dict[str, np.ndarray], sh_degree: int) -> bytes:
    """The compressed .ply bytes of Gaussians given as INRIA .ply columns, with `sh_degree` bands kept."""
    n, rest = len(columns["x"]), 3 * ((sh_degree + 1) ** 2 - 1)
    chunks = -(-n // CHUNK)
    pad = np.concatenate([np.arange(n), np.full(chunks * CHUNK - n, n - 1)])  # the last Gaussian repeated

    def get(names: list[str]) -> np.ndarray:  # (chunks, CHUNK, len(names))
        return np.stack([columns[c] for c in names], 1).astype(np.float64)[pad].reshape(chunks, CHUNK, -1)

    position, scale = get(["x", "y", "z"]), np.clip(get([f"scale_{i}" for i in range(3)]), -20, 20)
    color = get([f"f_dc_{i}" for i in range(3)]) * SH_C0 + 0.5
    ranges = [(a.min(1), a.max(1)) for a in (position, scale, color)]
    fractions = [_fraction(a, lo, hi) for a, (lo, hi) in zip((position, scale, color), ranges, strict=True)]
    alpha = 1.0 / (1.0 + np.exp(-get(["opacity"])[..., 0]))
    vertex = np.zeros((chunks * CHUNK, 4), "<u4")
    vertex[:, 0] = _pack_111011(fractions[0]).ravel()
    vertex[:, 1] = _pack_rotation(get([f"rot_{i}" for i in range(4)]).reshape(-1, 4))
    vertex[:, 2] = _pack_111011(fractions[1]).ravel()
    rgba = np.concatenate([fractions[2], alpha[..., None]], -1).reshape(-1, 4)
    vertex[:, 3] = sum(_unorm(rgba[:, i], 8) << (24 - 8 * i) for i in range(4))
    chunk = np.concatenate([ranges[0][0], ranges[0][1], ranges[1][0], ranges[1][1], ranges[2][0], ranges[2][1]], 1)
    header = ["ply", "format binary_little_endian 1.0", "comment written by splatfill", f"element chunk {chunks}"]
    header += [f"property float {f}" for f in CHUNK_FIELDS] + [f"element vertex {n}"]
    header += [f"property uint {f}" for f in VERTEX_FIELDS]
    body = [chunk.astype("<f4").tobytes(), vertex[:n].tobytes()]
    if rest:
        header += [f"element sh {n}"] + [f"property uchar f_rest_{i}" for i in range(rest)]
        sh = np.stack([columns[f"f_rest_{i}"] for i in range(rest)], 1).astype(np.float64)
        body.append(np.clip(np.trunc((sh / 8 + 0.5) * 256), 0, 255).astype(np.uint8).tobytes())
    return ("\n".join([*header, "end_header"]) + "\n").encode("ascii") + b"".join(body)


def decode(elements: list[tuple[str, int, list[tuple[str, str]]]], body: bytes, path: Path) -> dict[str, np.ndarray]:
    """INRIA .ply columns (float32) of a compressed .ply's elements ((name, count, fields) in file order, from its
    header) and the bytes after its header."""
    arrays, offset = {}, 0
    for name, count, fields in elements:
        dtype = np.dtype(fields)
        if offset + count * dtype.itemsize > len(body):
            raise InputError(f"{path} ends inside its {name} element: the file is cut short")
        arrays[name] = np.frombuffer(body, dtype, count, offset)
        offset += count * dtype.itemsize
    chunk, vertex = arrays.get("chunk"), arrays.get("vertex")
    if chunk is None or vertex is None or any(f not in chunk.dtype.names for f in CHUNK_FIELDS[:12]) or \
            any(f not in vertex.dtype.names for f in VERTEX_FIELDS):
        raise InputError(f"{path} is no compressed splat .ply (chunk and vertex elements with packed_* fields)")
    n = len(vertex)
    if len(chunk) != -(-n // CHUNK):
        raise InputError(f"{path} has {len(chunk)} chunks for {n} Gaussians, not one per {CHUNK}")
    of = np.arange(n) // CHUNK
    bounds = lambda names: np.stack([chunk[f].astype(np.float64) for f in names], 1)[of]  # noqa: E731
    columns = {}
    position = _lerp(_unpack_111011(vertex["packed_position"]), bounds(CHUNK_FIELDS[0:3]), bounds(CHUNK_FIELDS[3:6]))
    scale = _lerp(_unpack_111011(vertex["packed_scale"]), bounds(CHUNK_FIELDS[6:9]), bounds(CHUNK_FIELDS[9:12]))
    packed = vertex["packed_color"].astype(np.int64)
    rgba = np.stack([(packed >> (24 - 8 * i)) & 0xFF for i in range(4)], 1) / 255.0
    color = _lerp(rgba[:, :3], bounds(CHUNK_FIELDS[12:15]), bounds(CHUNK_FIELDS[15:18])) \
        if "min_r" in chunk.dtype.names else rgba[:, :3]
    alpha = np.clip(rgba[:, 3], 0.5 / 255, 1 - 0.5 / 255)
    quat = _unpack_rotation(vertex["packed_rotation"])
    columns |= {c: position[:, i] for i, c in enumerate(("x", "y", "z"))}
    columns |= {f"f_dc_{i}": (color[:, i] - 0.5) / SH_C0 for i in range(3)}
    if "sh" in arrays:
        sh = arrays["sh"]
        columns |= {f: ((sh[f].astype(np.float64) + 0.5) / 256 - 0.5) * 8 for f in sh.dtype.names}
    columns["opacity"] = np.log(alpha / (1 - alpha))
    columns |= {f"scale_{i}": scale[:, i] for i in range(3)}
    columns |= {f"rot_{i}": quat[:, i] for i in range(4)}
    return {c: np.asarray(v, np.float32) for c, v in columns.items()}


def parse_header(f, path: Path) -> list[tuple[str, int, list[tuple[str, str]]]]:
    """Every element's (name, count, [(field, dtype)]) from a binary little-endian .ply header (after `ply`)."""
    elements: list[tuple[str, int, list[tuple[str, str]]]] = []
    while (line := f.readline()) and line.strip() != b"end_header":
        words = line.decode("ascii", "replace").split()
        if words[:1] == ["element"] and len(words) == 3:
            elements.append((words[1], int(words[2]), []))
        elif words[:1] == ["property"] and elements:
            if len(words) != 3 or words[1] not in PLY_TYPES:
                raise InputError(f"{path}: property {' '.join(words[1:])} is not one of a splat .ply")
            elements[-1][2].append((words[2], "<" + PLY_TYPES[words[1]]))
    return elements


def _fraction(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    span = hi - lo
    safe = np.where(span < 1e-5, 1.0, span)[:, None]
    return np.where(span[:, None] < 1e-5, 0.0, np.clip((values - lo[:, None]) / safe, 0, 1))


def _unorm(values: np.ndarray, bits: int) -> np.ndarray:
    top = (1 << bits) - 1
    return np.clip(np.floor(values * top + 0.5), 0, top).astype(np.uint32)


def _pack_111011(fractions: np.ndarray) -> np.ndarray:
    return _unorm(fractions[..., 0], 11) << 21 | _unorm(fractions[..., 1], 10) << 11 | _unorm(fractions[..., 2], 11)


def _unpack_111011(packed: np.ndarray) -> np.ndarray:
    p = packed.astype(np.int64)
    return np.stack([(p >> 21 & 0x7FF) / 2047.0, (p >> 11 & 0x3FF) / 1023.0, (p & 0x7FF) / 2047.0], 1)


def _lerp(t: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return lo + t * (hi - lo)


def _pack_rotation(quat: np.ndarray) -> np.ndarray:
    q = quat / np.maximum(np.linalg.norm(quat, axis=1, keepdims=True), 1e-12)
    largest = np.abs(q).argmax(1)
    q = np.where(q[np.arange(len(q)), largest][:, None] < 0, -q, q)
    packed = largest.astype(np.uint32)
    for i in range(4):
        packed = np.where(largest == i, packed, packed << 10 | _unorm(q[:, i] * np.sqrt(0.5) + 0.5, 10))
    return packed


def _unpack_rotation(packed: np.ndarray) -> np.ndarray:
    p = packed.astype(np.int64)
    largest = p >> 30
    q = np.zeros((len(p), 4))
    for i in (3, 2, 1, 0):
        take = largest != i
        q[take, i] = ((p & 0x3FF) / 1023.0 - 0.5)[take] / np.sqrt(0.5)
        p = np.where(take, p >> 10, p)
    q[np.arange(len(q)), largest] = np.sqrt(np.maximum(0.0, 1.0 - (q ** 2).sum(1)))
    return q
