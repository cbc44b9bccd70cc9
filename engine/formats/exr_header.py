"""An OpenEXR file's header, checked in Python before OpenImageIO opens the file.

OpenEXR trusts its header: a file whose bytes shifted by two (a date string edited in place) made it
divide by zero and kill the whole process with SIGFPE, which no Python code can catch. So the header's
attributes are walked here first (layout: openexr.com, "OpenEXR File Layout"): every attribute's size must
fit the file, the ones OpenEXR divides or allocates by must hold sane values (channel sampling >= 1, tile
sizes >= 1, a data window of positive size within the pixel limit, a known compression and line order).
"""

from __future__ import annotations

import struct
from pathlib import Path

from ..base.errors import InputError
from .checks import check_pixels

MAGIC = 20000630
SINGLE_TILED, LONG_NAMES, NON_IMAGE, MULTIPART = 0x200, 0x400, 0x800, 0x1000
REQUIRED = {"channels": "chlist", "compression": "compression", "dataWindow": "box2i", "displayWindow": "box2i",
            "lineOrder": "lineOrder", "pixelAspectRatio": "float", "screenWindowCenter": "v2f",
            "screenWindowWidth": "float"}
FIXED_SIZES = {"box2i": 16, "compression": 1, "lineOrder": 1, "tiledesc": 9, "float": 4, "int": 4, "v2f": 8}
MAX_HEADER_BYTES = 1 << 24


def check_exr_header(path: Path) -> tuple[int, int]:
    """(width, height) of the first part, or InputError unless every part's header of the EXR at `path` is
    one OpenEXR can read safely."""
    with open(path, "rb") as f:
        data = f.read(MAX_HEADER_BYTES)
    if len(data) < 8 or struct.unpack_from("<i", data)[0] != MAGIC:
        raise InputError(f"{path} is not an OpenEXR file; replace it")
    flags = struct.unpack_from("<I", data, 4)[0]
    if flags & 0xFF != 2 or flags & ~0x1EFF:
        raise InputError(f"{path}: OpenEXR version field {flags:#x} is not one this reader knows; replace the file")
    pos, sizes = 8, []
    while True:
        header, pos = _attributes(data, pos, path)
        if not header:
            if not sizes:
                raise InputError(f"{path}: OpenEXR header holds no attributes; replace the file")
            return sizes[0]
        sizes.append(_check_part(header, bool(flags & (SINGLE_TILED | MULTIPART)), path))
        if not flags & MULTIPART:
            return sizes[0]


def _attributes(data: bytes, pos: int, path: Path) -> tuple[dict[str, tuple[str, bytes]], int]:
    """One header: {name: (type, value bytes)}, and the position after its terminating null byte."""
    header: dict[str, tuple[str, bytes]] = {}
    while True:
        name, pos = _string(data, pos, path)
        if not name:
            return header, pos
        kind, pos = _string(data, pos, path)
        if pos + 4 > len(data):
            raise InputError(f"{path}: OpenEXR header is truncated; replace the file")
        size = struct.unpack_from("<i", data, pos)[0]
        pos += 4
        if size < 0 or pos + size > len(data) or FIXED_SIZES.get(kind, size) != size:
            raise InputError(f"{path}: OpenEXR attribute {name!r} ({kind}) declares {size} bytes; the header "
                             "is corrupt, replace the file")
        header[name] = (kind, data[pos:pos + size])
        pos += size


def _string(data: bytes, pos: int, path: Path) -> tuple[str, int]:
    end = data.find(b"\0", pos, pos + 256)
    if end < 0:
        raise InputError(f"{path}: OpenEXR header is truncated or corrupt; replace the file")
    try:
        return data[pos:end].decode("ascii"), end + 1
    except UnicodeDecodeError:
        raise InputError(f"{path}: OpenEXR header holds a non-ASCII name; the file is corrupt, replace it") from None


def _check_part(header: dict[str, tuple[str, bytes]], tiled: bool, path: Path) -> tuple[int, int]:
    missing = [n for n, kind in REQUIRED.items() if header.get(n, ("",))[0] != kind]
    if missing:
        raise InputError(f"{path}: OpenEXR header lacks {', '.join(missing)} (or gives another type); the file "
                         "is corrupt, replace it")
    size, display = (_window(header[name][1]) for name in ("dataWindow", "displayWindow"))
    check_pixels(*size, path)
    check_pixels(*display, path)
    aspect = struct.unpack("<f", header["pixelAspectRatio"][1])[0]
    if not 1e-6 < aspect < 1e6:
        raise InputError(f"{path}: OpenEXR pixel aspect ratio {aspect} is not positive; the file is corrupt")
    if header["compression"][1][0] > 9 or header["lineOrder"][1][0] > 2:
        raise InputError(f"{path}: OpenEXR compression or line order is unknown; the file is corrupt")
    _check_channels(header["channels"][1], path)
    if "tiles" in header or tiled and header.get("type", ("", b""))[1].startswith(b"tiled"):
        if "tiles" not in header:
            raise InputError(f"{path}: tiled OpenEXR without a tiles attribute; the file is corrupt")
        xs, ys = struct.unpack_from("<II", header["tiles"][1])
        if not (0 < xs <= 1 << 16 and 0 < ys <= 1 << 16):
            raise InputError(f"{path}: OpenEXR tile size {xs}x{ys} is not positive; the file is corrupt")
    return size


def _window(box: bytes) -> tuple[int, int]:
    """(width, height) of a box2i (xmin, ymin, xmax, ymax, inclusive)."""
    x0, y0, x1, y1 = struct.unpack("<4i", box)
    return x1 - x0 + 1, y1 - y0 + 1


def _check_channels(chlist: bytes, path: Path) -> None:
    """Channel list: name, pixel type (0..2), pLinear, 3 reserved bytes, x and y sampling (>= 1 each)."""
    pos, count = 0, 0
    while pos < len(chlist) and chlist[pos] != 0:
        name, pos = _string(chlist, pos, path)
        if pos + 16 > len(chlist):
            raise InputError(f"{path}: OpenEXR channel list is truncated; the file is corrupt")
        pixel_type, _, xs, ys = struct.unpack_from("<iI2i", chlist, pos)
        if pixel_type not in (0, 1, 2) or xs < 1 or ys < 1:
            raise InputError(f"{path}: OpenEXR channel {name!r} has type {pixel_type} and sampling {xs}x{ys}; "
                             "the file is corrupt, replace it")
        pos, count = pos + 16, count + 1
    if count == 0:
        raise InputError(f"{path}: OpenEXR file has no channels; replace it")
