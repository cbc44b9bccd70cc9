"""Every splat file format the engine and Blender read and write, behind one reader and one writer: the standard
INRIA .ply (engine.formats.splat_ply), the compressed .ply of SuperSplat (compressed_ply), antimatter15's
.splat (dot_splat) and Niantic's .spz (spz). Whatever comes in becomes the .ply's fields, so every later stage
sees one layout; numpy only, so Blender's side shares it.

The format is told by the suffix (.splat, .spz) or, for a .ply, by its first element (`chunk`: compressed).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..base.errors import InputError
from . import compressed_ply, dot_splat, spz
from .checks import LIMITS, check_count
from .splat_ply import SH_REST_COUNTS, read_vertices, write_vertices

FORMATS = ("ply", "compressed-ply", "splat", "spz")
SUFFIX = {"ply": ".ply", "compressed-ply": ".compressed.ply", "splat": ".splat", "spz": ".spz"}
BASE = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"]
TAIL = ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]


def format_of(path: Path) -> str:
    """The format a file is in (or, for a path not written yet, the one its name asks for)."""
    name = Path(path).name.lower()
    if name.endswith(".splat"):
        return "splat"
    if name.endswith(".spz"):
        return "spz"
    if name.endswith(".compressed.ply"):
        return "compressed-ply"
    if name.endswith(".ply") and Path(path).is_file() and _is_compressed(Path(path)):
        return "compressed-ply"
    if name.endswith(".ply"):
        return "ply"
    raise InputError(f"{path}: a splat file ends in .ply, .compressed.ply, .splat or .spz")


def read_splat_file(path: Path) -> np.ndarray:
    """The Gaussians of any splat file as a structured array of the INRIA .ply's float32 fields (what
    `splat_ply.read_vertices` gives for a .ply)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"missing Gaussian file {path}: train a scene first or pass the right path")
    kind = format_of(path)
    if kind == "ply":
        return read_vertices(path)
    if kind == "compressed-ply":
        with open(path, "rb") as f:
            f.readline()
            elements = compressed_ply.parse_header(f, path)
            columns = compressed_ply.decode(elements, f.read(), path)
    else:
        data = path.read_bytes()
        columns = dot_splat.decode(data, path) if kind == "splat" else spz.decode(data, path)
    check_count(len(columns["x"]), "Gaussians", LIMITS.gaussians, "--limit-gaussians", path)
    return _structured(columns)


def write_splat_file(path: Path, vertices: np.ndarray, kind: str, sh_degree: int | None = None,
                     identities: bool = False) -> None:
    """Write Gaussians (a structured array of .ply fields) as `kind` at `path`, atomically; `sh_degree` keeps
    that many SH bands (default all the file has; .splat keeps none), `identities` keeps our obj_dc_* fields
    (.ply only: no other format has a place for them)."""
    if kind not in FORMATS:
        raise InputError(f"--format {kind}: give one of {', '.join(FORMATS)}")
    names = vertices.dtype.names
    held = SH_REST_COUNTS.get(sum(1 for n in names if n.startswith("f_rest_")), 0)
    degree = held if sh_degree is None else sh_degree
    if not 0 <= degree <= held:
        raise InputError(f"--sh-degree {sh_degree}: the scene holds SH degree {held} (0 to {held})")
    if kind == "splat":
        degree = 0
    rest = [f"f_rest_{c * ((held + 1) ** 2 - 1) + i}" for c in range(3) for i in range((degree + 1) ** 2 - 1)]
    zeros = np.zeros(len(vertices), np.float32)
    columns = {n: vertices[n] if n in names else zeros for n in BASE}  # in the .ply's order
    columns |= {f"f_rest_{i}": vertices[n] for i, n in enumerate(rest)}
    columns |= {n: vertices[n] for n in TAIL}
    if identities and kind == "ply":
        columns |= {n: vertices[n] for n in names if n.startswith("obj_dc_")}
    path = Path(path)
    if kind == "ply":
        write_vertices(path, columns)
        return
    data = (compressed_ply.encode(columns, degree) if kind == "compressed-ply" else
            dot_splat.encode(columns) if kind == "splat" else spz.encode(columns, degree))
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(data)
    tmp.replace(path)


def _is_compressed(path: Path) -> bool:
    with open(path, "rb") as f:
        head = f.read(4096)
    end = head.find(b"end_header")
    return b"element chunk " in (head[:end] if end >= 0 else head)


def _structured(columns: dict[str, np.ndarray]) -> np.ndarray:
    rest = sorted((c for c in columns if c.startswith("f_rest_")), key=lambda c: int(c[7:]))
    names = [*BASE, *rest, *TAIL]
    out = np.zeros(len(columns["x"]), [(n, "<f4") for n in names])
    for n in names:
        if n in columns:
            out[n] = columns[n]
    return out
