"""Read a 3DGS .ply (engine.io.ply_io's layout, which is the standard one) with numpy alone, and turn it into
what a Blender proxy shows: position, rotation, scale, colour, opacity and the identity group.

Blender's Python has numpy but neither torch nor plyfile, so this is the Blender side's reader; it needs no
bpy either, so the tests check it without Blender. The groups come from the run's classifier.npz (the
engine writes it numpy-only for this reason): argmax of the per-Gaussian class logits.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

SH_C0 = 0.28209479177387814  # the DC spherical-harmonic basis value: colour = 0.5 + C0 * f_dc
PLY_TYPES = {"float": "f4", "float32": "f4", "double": "f8", "float64": "f8", "uchar": "u1", "uint8": "u1",
             "char": "i1", "int8": "i1", "ushort": "u2", "uint16": "u2", "short": "i2", "int16": "i2",
             "uint": "u4", "uint32": "u4", "int": "i4", "int32": "i4"}


class SplatFileError(ValueError):
    """A .ply or its companions cannot be read; the message names the file and the fix."""


@dataclass
class Splats:
    positions: np.ndarray  # (N, 3) float32
    rotations: np.ndarray  # (N, 4) float32 unit quaternions, w x y z
    scales: np.ndarray  # (N, 3) float32, standard deviations in world units
    colors: np.ndarray  # (N, 4) float32 linear RGB from the SH DC term, alpha = opacity
    groups: np.ndarray  # (N,) int32 identity group (0 without a classifier)
    names: dict[int, str]  # group id -> object name


def read_vertices(path: Path) -> np.ndarray:
    """The vertex element of a binary little-endian .ply as a structured array."""
    try:
        with open(path, "rb") as f:
            if f.readline().strip() != b"ply":
                raise SplatFileError(f"{path} is not a PLY file; export the splats as a 3DGS .ply")
            fields, count, fmt, in_vertex = [], 0, "", False
            while (line := f.readline()) and line.strip() != b"end_header":
                words = line.decode("ascii", "replace").split()
                if words[:1] == ["format"]:
                    fmt = words[1]
                elif words[:1] == ["element"]:
                    in_vertex = words[1] == "vertex"
                    count = int(words[2]) if in_vertex else count
                elif words[:1] == ["property"] and in_vertex:
                    if words[1] == "list" or words[1] not in PLY_TYPES:
                        raise SplatFileError(f"{path}: vertex property {' '.join(words[1:])} is not a 3DGS field")
                    fields.append((words[2], "<" + PLY_TYPES[words[1]]))
            if fmt != "binary_little_endian":
                raise SplatFileError(f"{path} is {fmt or 'not'} binary_little_endian; save it as a binary 3DGS .ply")
            data = np.frombuffer(f.read(count * np.dtype(fields).itemsize), dtype=fields, count=count)
    except OSError as exc:
        raise SplatFileError(f"cannot read {path} ({exc.strerror}); check the path") from exc
    except (ValueError, IndexError) as exc:
        if isinstance(exc, SplatFileError):
            raise
        raise SplatFileError(f"{path} is truncated or corrupt ({exc}); re-export it") from exc
    missing = [n for n in ("x", "y", "z", "f_dc_0", "opacity", "scale_0", "rot_0") if n not in data.dtype.names]
    if missing:
        raise SplatFileError(f"{path} lacks 3DGS properties {', '.join(missing)}; is it a Gaussian splat .ply?")
    return data


def read_splats(path: Path) -> Splats:
    """The proxies' data for `path`, grouped by identity when a classifier.npz sits beside it or in the
    run folder above it (a removal's output lies in RUN/removed/)."""
    path = Path(path)
    v = read_vertices(path)
    columns = lambda prefix, n: np.stack([v[f"{prefix}{i}"] for i in range(n)], axis=1).astype(np.float32)  # noqa: E731
    rotations = columns("rot_", 4)
    rotations /= np.maximum(np.linalg.norm(rotations, axis=1, keepdims=True), 1e-12)
    rgb = np.clip(0.5 + SH_C0 * columns("f_dc_", 3), 0.0, 1.0)
    alpha = 1.0 / (1.0 + np.exp(-v["opacity"].astype(np.float32)))
    groups = np.zeros(len(v), np.int32)
    names = {0: "background"}
    classifier = _companion(path, "classifier.npz")
    identity = [f"obj_dc_{i}" for i in range(16)]
    if classifier is not None and all(n in v.dtype.names for n in identity):
        try:
            with np.load(classifier) as c:
                weight, bias = c["weight"].astype(np.float32), c["bias"].astype(np.float32)
        except (OSError, ValueError, KeyError) as exc:
            raise SplatFileError(f"cannot read {classifier} ({exc}); re-run training") from exc
        groups = (columns("obj_dc_", 16) @ weight.T + bias).argmax(1).astype(np.int32)
        names = _object_names(path, len(bias))
    return Splats(positions=np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float32), rotations=rotations,
                  scales=np.exp(columns("scale_", 3)), colors=np.concatenate([rgb, alpha[:, None]], 1),
                  groups=groups, names=names)


def _companion(path: Path, name: str) -> Path | None:
    for folder in (path.parent, path.parent.parent):
        if (folder / name).is_file():
            return folder / name
    return None


def _object_names(path: Path, classes: int) -> dict[int, str]:
    """Names from the training scene's masks/objects.json (the run's config.json names the scene)."""
    names = {i: f"object_{i}" for i in range(classes)}
    names[0] = "background"
    config = _companion(path, "config.json")
    try:
        scene = Path(json.loads(config.read_text())["scene"]) if config else None
        entries = json.loads((scene / "masks" / "objects.json").read_text()) if scene else []
    except (OSError, ValueError, KeyError):
        return names
    names.update({int(e["id"]): str(e["name"]) for e in entries if int(e["id"]) < classes})
    return names
