"""What every reader checks before it trusts a file: limits on what a header may ask for, JSON of bounded
depth with finite numbers, camera intrinsics and poses that can be rendered, image sizes read from the
header before any pixel is decoded.

A file declares its own sizes (a PLY's vertex count, an npy header's shape, a PNG's width and height); no
reader allocates from such a field before it is checked here against these limits and against the bytes
the file really holds. The limits sit far above any real scene and can be raised from the CLI
(`python -m engine --limit-pixels N --limit-gaussians N ...`) or the environment (SPLATFILL_LIMIT_PIXELS,
SPLATFILL_LIMIT_GAUSSIANS). numpy and the standard library only: Blender's side reads the same files.
"""

from __future__ import annotations

import json
import math
import os
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import InputError

JSON_DEPTH = 32  # our JSON files nest 3 deep; a file nested deeper is not one of them
JSON_BYTES = 256 << 20  # a scene's largest JSON (cameras.json of 10k views) is a few MB
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@dataclass
class Limits:
    pixels: int = int(os.environ.get("SPLATFILL_LIMIT_PIXELS", 200_000_000))  # per image: 16k x 12k
    gaussians: int = int(os.environ.get("SPLATFILL_LIMIT_GAUSSIANS", 50_000_000))  # per .ply: 12 GB of float32


LIMITS = Limits()


def check_pixels(width: int, height: int, path: Path | str) -> None:
    """An image size a reader may allocate for: positive, and within LIMITS.pixels."""
    if not (isinstance(width, int) and isinstance(height, int)) or width < 1 or height < 1:
        raise InputError(f"{path}: image size {width}x{height} is not positive; re-export the file")
    if width * height > LIMITS.pixels:
        raise InputError(f"{path}: {width}x{height} is {width * height:,} pixels, over the limit of "
                         f"{LIMITS.pixels:,}; downscale the images or raise --limit-pixels")


def check_count(count: int, what: str, limit: int, flag: str, path: Path | str) -> None:
    if count < 0 or count > limit:
        raise InputError(f"{path} declares {count:,} {what}, over the limit of {limit:,}; the file is corrupt "
                         f"or raise {flag}")


def read_json(path: Path | str):
    """A JSON file's value: nested at most JSON_DEPTH deep, every number finite (1e400 and NaN refused)."""
    path = Path(path)
    try:
        if path.stat().st_size > JSON_BYTES:
            raise InputError(f"{path} is {path.stat().st_size:,} bytes, more than any splatfill JSON file "
                             f"({JSON_BYTES:,}); is it the right file?")
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot read {path} ({exc.strerror}); check the path") from exc
    except UnicodeDecodeError as exc:
        raise InputError(f"{path} is not UTF-8 text; fix or regenerate it") from exc
    if _depth(text) > JSON_DEPTH:
        raise InputError(f"{path} nests deeper than {JSON_DEPTH} levels; it is not a splatfill file")
    try:
        return json.loads(text, parse_float=_finite_float, parse_constant=_no_constant)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path} is not valid JSON ({exc.args[0]}); fix or regenerate it") from exc
    except ValueError as exc:
        raise InputError(f"{path}: {exc}; fix or regenerate it") from exc


def _depth(text: str) -> int:
    """Deepest bracket nesting outside strings, counted without parsing (json recurses per level)."""
    depth = deepest = 0
    in_string = escaped = False
    for ch in text:
        if in_string:
            escaped, in_string = (False, True) if escaped else (ch == "\\", ch != '"')
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"number {text[:20]} is out of range")
    return value


def _no_constant(name: str) -> float:
    raise ValueError(f"{name} is not a number a splatfill file holds")


def finite_number(value, what: str, path: Path | str, positive: bool = False) -> float:
    """`value` as a finite float (positive if asked), or a one-line error naming the field."""
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{path}: {what} is {str(value)[:40]!r}, not a number; fix the file") from None
    if not math.isfinite(number) or (positive and number <= 0):
        raise InputError(f"{path}: {what} is {number}, not a {'positive ' if positive else ''}finite number; "
                         "fix the file")
    return number


def check_intrinsics(width, height, fx, fy, cx, cy, path: Path | str, name: str) -> tuple[int, int, float, float,
                                                                                          float, float]:
    """A camera's size and focal lengths as a renderer needs them (sizes whole and within the pixel limit,
    focal lengths positive, principal point finite)."""
    w, h = (finite_number(v, f"{name} {k}", path, positive=True) for k, v in (("width", width), ("height", height)))
    if w != int(w) or h != int(h):
        raise InputError(f"{path}: {name} size {w}x{h} is not whole pixels; fix the file")
    check_pixels(int(w), int(h), f"{path} ({name})")
    return (int(w), int(h), finite_number(fx, f"{name} fx", path, True), finite_number(fy, f"{name} fy", path, True),
            finite_number(cx, f"{name} cx", path), finite_number(cy, f"{name} cy", path))


def check_pose(R, t, path: Path | str, name: str) -> tuple[np.ndarray, np.ndarray]:
    """World-to-camera R (a rotation: 3x3, orthonormal within 1e-3) and t (3 finite numbers)."""
    try:
        R, t = np.asarray(R, dtype=np.float64), np.asarray(t, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{path}: {name} pose is not numeric; fix the file") from None
    if R.shape != (3, 3) or t.shape != (3,) or not (np.isfinite(R).all() and np.isfinite(t).all()):
        raise InputError(f"{path}: {name} pose needs R 3x3 and t of 3 finite numbers (got {R.shape}, {t.shape}); "
                         "fix the file")
    if np.abs(R @ R.T - np.eye(3)).max() > 1e-3 or np.linalg.det(R) < 0:
        raise InputError(f"{path}: {name} R is not a rotation; fix the file")
    return R, t


def unit_quaternion(q, path: Path | str, name: str) -> np.ndarray:
    """A rotation quaternion (w, x, y, z) normalised, refused if not finite or near zero."""
    q = np.asarray(q, dtype=np.float64)
    with np.errstate(over="ignore"):
        norm = float(np.linalg.norm(q)) if np.isfinite(q).all() else 0.0
    if not np.isfinite(norm):
        norm = 0.0
    if norm < 1e-8:
        raise InputError(f"{path}: {name} rotation quaternion {q.tolist()} cannot be normalised; fix the model")
    return q / norm


def png_size(path: Path) -> tuple[int, int] | None:
    """(width, height) from a PNG's IHDR chunk, or None when the file is no PNG (read 24 bytes only)."""
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or not head.startswith(PNG_SIGNATURE):
        return None
    if head[12:16] != b"IHDR":
        raise InputError(f"{path}: PNG without an IHDR header; the file is corrupt, replace it")
    width, height = struct.unpack(">II", head[16:24])
    return width, height
