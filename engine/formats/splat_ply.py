"""The standard 3DGS .ply layout, plus Gaussian Grouping's identity as obj_dc_0..15, read and written with
numpy alone (the engine and Blender's Python share this one reader; Blender has neither torch nor plyfile).

Properties, in the order the reference code writes them:
  x y z nx ny nz f_dc_0..2 f_rest_0..(3K-1) opacity scale_0..2 rot_0..3 [obj_dc_0..15]
f_rest is channel-major (all K coefficients of red, then green, then blue), rot is w, x, y, z; opacity is
a logit and scales are logs, exactly as stored in training. Ordinary splat viewers ignore obj_dc_*.
The classifier goes beside the .ply as classifier.npz (weight (C, 16), bias (C,)), so that Blender-side
code can group Gaussians by identity without torch. Colour from the DC term: rgb = 0.5 + SH_C0 * f_dc.
"""

from __future__ import annotations

import zipfile
import zlib
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from .checks import LIMITS, check_count

IDENTITY_DIM = 16  # Gaussian Grouping's identity encoding
MAX_CLASSES = 256  # object ids are 8-bit, as in the masks
SH_REST_COUNTS = {0: 0, 9: 1, 24: 2, 45: 3}  # number of f_rest properties -> SH degree
# Real spherical-harmonic constants of the reference 3DGS code and gsplat, bands 0..3.
SH_C0 = 0.28209479177387814
SH_C1 = 0.4886025119029199
SH_C2 = (1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396)
SH_C3 = (-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154, -0.4570457994644658,
         1.445305721320277, -0.5900435899266435)
# The bands above 0 as polynomials of the unit direction (x, y, z), for code that cannot call
# engine.render.sh (Blender's shader nodes): basis k + 1 = sum of coefficient * x^a y^b z^c over its terms.
SH_POLYNOMIALS: tuple[tuple[tuple[float, tuple[int, int, int]], ...], ...] = (
    ((-SH_C1, (0, 1, 0)),), ((SH_C1, (0, 0, 1)),), ((-SH_C1, (1, 0, 0)),),
    ((SH_C2[0], (1, 1, 0)),), ((SH_C2[1], (0, 1, 1)),),
    ((2 * SH_C2[2], (0, 0, 2)), (-SH_C2[2], (2, 0, 0)), (-SH_C2[2], (0, 2, 0))),
    ((SH_C2[3], (1, 0, 1)),), ((SH_C2[4], (2, 0, 0)), (-SH_C2[4], (0, 2, 0))),
    ((3 * SH_C3[0], (2, 1, 0)), (-SH_C3[0], (0, 3, 0))), ((SH_C3[1], (1, 1, 1)),),
    ((4 * SH_C3[2], (0, 1, 2)), (-SH_C3[2], (2, 1, 0)), (-SH_C3[2], (0, 3, 0))),
    ((2 * SH_C3[3], (0, 0, 3)), (-3 * SH_C3[3], (2, 0, 1)), (-3 * SH_C3[3], (0, 2, 1))),
    ((4 * SH_C3[4], (1, 0, 2)), (-SH_C3[4], (3, 0, 0)), (-SH_C3[4], (1, 2, 0))),
    ((SH_C3[5], (2, 0, 1)), (-SH_C3[5], (0, 2, 1))),
    ((SH_C3[6], (3, 0, 0)), (-3 * SH_C3[6], (1, 2, 0))),
)
PLY_TYPES = {"float": "f4", "float32": "f4", "double": "f8", "float64": "f8", "uchar": "u1", "uint8": "u1",
             "char": "i1", "int8": "i1", "ushort": "u2", "uint16": "u2", "short": "i2", "int16": "i2",
             "uint": "u4", "uint32": "u4", "int": "i4", "int32": "i4"}
REQUIRED = ("x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2",
            "rot_0", "rot_1", "rot_2", "rot_3")


def property_names(k: int, with_identity: bool) -> list[str]:
    """The vertex properties of a .ply with `k` higher-order SH coefficients per channel, in file order."""
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"]
    names += [f"f_rest_{i}" for i in range(3 * k)]
    names += ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    if with_identity:
        names += [f"obj_dc_{i}" for i in range(IDENTITY_DIM)]
    return names


def read_vertices(path: Path) -> np.ndarray:
    """The vertex element of a binary little-endian 3DGS .ply as a structured array, its fields checked."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"missing Gaussian file {path}: train a scene first or pass the right path")
    try:
        with open(path, "rb") as f:
            fields, count = _read_header(f, path)
            check_count(count, "Gaussians", LIMITS.gaussians, "--limit-gaussians", path)
            size, left = np.dtype(fields).itemsize, path.stat().st_size - f.tell()
            if count * size > left:
                raise InputError(f"{path} declares {count:,} Gaussians of {size} bytes but holds {left:,} bytes; "
                                 "it is truncated, re-export it")
            data = np.frombuffer(f.read(count * size), dtype=fields, count=count)
    except OSError as exc:
        raise InputError(f"cannot read {path} ({exc.strerror}); check the path") from exc
    except (ValueError, IndexError, TypeError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(f"{path} is truncated or corrupt ({exc}); re-export it") from exc
    names = set(data.dtype.names)
    missing = [n for n in REQUIRED if n not in names]
    rest = {n for n in names if n.startswith("f_rest_")}
    if missing or len(rest) not in SH_REST_COUNTS or rest != {f"f_rest_{i}" for i in range(len(rest))}:
        lacking = ", ".join(missing) or f"f_rest_0..{len(rest) - 1} ({len(rest)} f_rest fields, as 0, 9, 24 or 45)"
        raise InputError(f"{path} is not a 3DGS .ply: missing {lacking}")
    if count == 0:
        raise InputError(f"{path} holds no Gaussians; export a trained scene")
    return data


def _read_header(f, path: Path) -> tuple[list[tuple[str, str]], int]:
    """The vertex element's (name, dtype) fields and count; the vertex element must come first."""
    if f.readline().strip() != b"ply":
        raise InputError(f"{path} is not a PLY file; export the splats as a 3DGS .ply")
    fields, count, fmt, element = [], 0, "", ""
    while (line := f.readline()) and line.strip() != b"end_header":
        words = line.decode("ascii", "replace").split()
        if words[:1] == ["format"] and len(words) > 1:
            fmt = words[1]
        elif words[:1] == ["element"] and len(words) > 2:
            if not element and words[1] != "vertex":
                raise InputError(f"{path}: its first element is {words[1]!r}, not vertex; is it a splat .ply?")
            element = words[1]
            count = int(words[2]) if element == "vertex" else count
        elif words[:1] == ["property"] and element == "vertex":
            if len(words) != 3 or words[1] not in PLY_TYPES:
                raise InputError(f"{path}: vertex property {' '.join(words[1:])} is not a 3DGS field")
            fields.append((words[2], "<" + PLY_TYPES[words[1]]))
    if fmt != "binary_little_endian":
        raise InputError(f"{path} is {fmt or 'not'} binary_little_endian; save it as a binary 3DGS .ply")
    if not fields or count < 0:
        raise InputError(f"{path} has no vertex properties; is it a Gaussian splat .ply?")
    return fields, count


def write_vertices(path: Path, columns: dict[str, np.ndarray]) -> None:
    """Write float32 columns (each (N,), in file order) as a binary little-endian .ply, atomically."""
    n = len(next(iter(columns.values())))
    vertex = np.empty(n, dtype=[(name, "<f4") for name in columns])
    for name, values in columns.items():
        vertex[name] = values
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {n}"]
    header += [f"property float {name}" for name in columns] + ["end_header"]
    path = Path(path)
    tmp = path.with_suffix(".ply.tmp")
    with open(tmp, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        f.write(vertex.tobytes())
    tmp.replace(path)


def read_classifier(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """classifier.npz as float32 weight (C, 16) and bias (C,), C at most MAX_CLASSES. The arrays' headers
    are checked before any is loaded: a corrupt header must not ask for gigabytes."""
    try:
        with zipfile.ZipFile(path) as archive:
            shapes = {name: _npy_header(archive, f"{name}.npy") for name in ("weight", "bias")}
            (classes, *rest), bias = shapes["weight"], shapes["bias"]
            if rest != [IDENTITY_DIM] or bias != (classes,) or not 0 < classes <= MAX_CLASSES:
                raise InputError(f"classifier {path} has weight {shapes['weight']} and bias {bias}, not (C, "
                                 f"{IDENTITY_DIM}) and (C,) with C in 1..{MAX_CLASSES}; re-run training")
            with np.load(path, allow_pickle=False) as data:
                weight, bias = data["weight"].astype(np.float32), data["bias"].astype(np.float32)
    except InputError:
        raise
    except (OSError, KeyError, ValueError, EOFError, RuntimeError, NotImplementedError, zipfile.BadZipFile,
            zlib.error) as exc:  # zipfile raises RuntimeError for 'encrypted', NotImplementedError for a method
        raise InputError(f"cannot read classifier {path} ({str(exc)[:120]}); re-run training") from exc
    if not (np.isfinite(weight).all() and np.isfinite(bias).all()):
        raise InputError(f"classifier {path} holds NaN or infinite weights; re-run training")
    return weight, bias


def _npy_header(archive: zipfile.ZipFile, member: str) -> tuple:
    """The shape in one .npy member's header, its dtype checked to be numeric (no data read)."""
    with archive.open(member) as f:
        version = np.lib.format.read_magic(f)
        read = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
        shape, _, dtype = read(f)
    if dtype.kind not in "fiu":
        raise ValueError(f"{member} holds {dtype}, not numbers")
    return tuple(shape)


def write_classifier(path: Path, weight: np.ndarray, bias: np.ndarray) -> None:
    path = Path(path)
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, weight=weight, bias=bias)
    tmp.replace(path)
