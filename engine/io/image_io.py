"""Reading and writing the images of a scene folder: PNG (colour, ids, masks) and EXR (depth).

Conventions: colour arrays are (H, W, 3) uint8 RGB; id masks (H, W) uint8; depth (H, W) float32
z-depth along the camera axis in scene units (inf where no surface).
"""

from __future__ import annotations

import zlib  # noqa: F401  -- must load before pycolmap anywhere in the process (see colmap_model)
from pathlib import Path

import cv2
import numpy as np

from engine.base.c_streams import captured_c_output
from engine.base.errors import InputError
from engine.formats.checks import check_pixels, png_size
from engine.formats.exr_header import check_exr_header


def read_png(path: Path, kind: str = "image", size: tuple[int, int] | None = None) -> np.ndarray:
    """Read a PNG (or any format OpenCV reads) as RGB uint8 (H, W, 3), or (H, W) for masks. A PNG's size
    is checked from its header before decoding (a small file may declare a huge image): within the pixel
    limit, and equal to `size` (width, height) when given, as a view's camera gives it."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"missing {kind} file {path}: restore it or regenerate the scene")
    declared = png_size(path)
    if declared is not None:
        check_pixels(*declared, path)
        _check_size(path, declared, size)
    flag = cv2.IMREAD_UNCHANGED if kind == "mask" else cv2.IMREAD_COLOR
    with captured_c_output() as said:
        array = cv2.imread(str(path), flag)
    if array is None:
        why = f" ({said[0][:120]})" if said else ""
        raise InputError(f"cannot decode {kind} file {path}{why}: it is corrupt or not an image; replace it")
    if kind == "mask":
        if array.ndim == 3:
            array = array[..., 0]
        if array.dtype != np.uint8:
            raise InputError(f"mask {path} is {array.dtype}; masks must be 8-bit id PNGs (0 = background)")
        return array
    return cv2.cvtColor(array, cv2.COLOR_BGR2RGB)


def write_png(path: Path, array: np.ndarray) -> None:
    """Write (H, W, 3) RGB or (H, W) single-channel uint8 as PNG, creating the folder, whatever `path`'s suffix.
    Why not by suffix: a stage names each view's file after its photo, so a capture's masks, holes, renders and
    inpainted views were named IMG_0005.jpg and OpenCV wrote them as JPEG. A hole mask read back (> 0) then
    grew by the JPEG's ringing: 1,983 pixels for the 1,414 written, in the README path's IMG_0005."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    array = np.ascontiguousarray(array)
    if array.ndim == 3:
        array = cv2.cvtColor(array, cv2.COLOR_RGB2BGR)
    ok, data = cv2.imencode(".png", array)
    if not ok:
        raise InputError(f"cannot encode {path} as PNG: it needs (H, W) or (H, W, 3) uint8 pixels")
    try:
        path.write_bytes(data.tobytes())
    except OSError as exc:
        raise InputError(f"cannot write {path} ({exc.strerror}): check that the folder is writable") from exc


def _check_size(path: Path, declared: tuple[int, int], size: tuple[int, int] | None) -> None:
    if size is not None and tuple(declared) != tuple(size):
        raise InputError(f"{path} is {declared[0]}x{declared[1]} but its camera is {size[0]}x{size[1]}; resize it "
                         "or fix the COLMAP camera")


def read_exr_channels(path: Path, size: tuple[int, int] | None = None) -> dict[str, np.ndarray]:
    """All channels of an EXR, single- or multi-part, as {channel name: (H, W) float32}; its header checked
    first (and its size against `size`, width and height, when given)."""
    import OpenImageIO as oiio  # only EXR needs it; training-only machines can do without

    path = Path(path)
    if not path.is_file():
        raise InputError(f"missing EXR file {path}: restore it or regenerate the scene")
    _check_size(path, check_exr_header(path), size)  # OpenEXR itself crashes (SIGFPE) on some corrupt headers
    channels: dict[str, np.ndarray] = {}
    with captured_c_output():
        parts = _exr_parts(oiio, path)
        for part, spec in enumerate(parts):
            sub = oiio.ImageBuf(str(path), part, 0)
            pixels = sub.get_pixels(oiio.FLOAT)
            failed = sub.has_error and bool(sub.geterror())  # taken, or OpenImageIO prints it at exit
            if failed or pixels is None or pixels.size != spec.width * spec.height * spec.nchannels:
                raise InputError(f"cannot read EXR {path} part {part}: the file is truncated or corrupt; replace it")
            pixels = pixels.reshape(spec.height, spec.width, -1)
            for k, name in enumerate(spec.channelnames):
                channels[name] = pixels[..., k].astype(np.float32)
    return channels


def _exr_parts(oiio, path: Path) -> list:
    """Each part's header (size checked against the pixel limit), read before any pixel is decoded."""
    image = oiio.ImageInput.open(str(path))
    if image is None:
        try:
            message = oiio.geterror()
        except UnicodeDecodeError:  # the library's message may quote the file's bytes
            message = "unreadable header"
        first = (message.splitlines() or ["not an image"])[0][:120]
        raise InputError(f"cannot read EXR {path}: {first}; replace the file")
    specs = []
    try:
        while image.seek_subimage(len(specs), 0):
            spec = image.spec()
            check_pixels(spec.width, spec.height * max(spec.nchannels, 1), path)
            specs.append(spec)
    finally:
        image.close()
    if not specs:
        raise InputError(f"cannot read EXR {path}: it holds no image; replace the file")
    return specs


def exr_name(name: str) -> str:
    """The depth file beside an image: 0001.png -> 0001.exr."""
    return str(Path(name).with_suffix(".exr"))


def read_depth(path: Path, size: tuple[int, int] | None = None) -> np.ndarray:
    """Read a one-channel depth EXR as (H, W) float32 (of `size`, width and height, when given)."""
    channels = read_exr_channels(path, size)
    if len(channels) != 1:
        raise InputError(f"depth EXR {path} has channels {sorted(channels)}; expected one (Y or Z)")
    return next(iter(channels.values()))


def write_depth(path: Path, depth: np.ndarray) -> None:
    """Write (H, W) float32 depth as a one-channel EXR (channel 'Y').

    OpenImageIO scrambles a 2-D array silently, so it is given (H, W, 1). The folder is created.
    """
    import OpenImageIO as oiio

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    depth = np.ascontiguousarray(depth, dtype=np.float32)[..., None]
    spec = oiio.ImageSpec(depth.shape[1], depth.shape[0], 1, oiio.FLOAT)
    spec.channelnames = ("Y",)
    spec.attribute("compression", "zip")
    out = oiio.ImageOutput.create(str(path))
    if out is None or not out.open(str(path), spec):
        raise InputError(f"cannot write {path}: check that the folder exists and is writable")
    ok = out.write_image(depth)
    out.close()
    if not ok:
        raise InputError(f"writing {path} failed: {out.geterror()}")


def linear_to_srgb(rgb: np.ndarray) -> np.ndarray:
    """Scene-linear values (float, >= 0; above 1 the curve goes on) to sRGB-encoded ones: the sRGB transfer
    function, Blender's 'Standard' view transform."""
    rgb = np.maximum(rgb, 0.0)
    return np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * np.power(rgb, 1 / 2.4) - 0.055)


def srgb_to_linear(srgb: np.ndarray) -> np.ndarray:
    """sRGB-encoded values (float, >= 0) back to scene-linear ones: linear_to_srgb's inverse."""
    srgb = np.maximum(srgb, 0.0)
    return np.where(srgb <= 0.04045, srgb / 12.92, np.power((srgb + 0.055) / 1.055, 2.4))


def linear_to_srgb8(rgb: np.ndarray) -> np.ndarray:
    """Scene-linear RGB (float) to 8-bit sRGB: Blender's 'Standard' view transform, no dither."""
    return np.round(linear_to_srgb(np.clip(rgb, 0.0, 1.0)) * 255.0).astype(np.uint8)
