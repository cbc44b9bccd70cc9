"""A user's photos or video as the images SfM and training read: upright, at most `max_size` px, no EXIF.

Phones store a portrait photo as landscape pixels with an EXIF orientation tag. COLMAP reads the stored
pixels and ignores the tag, OpenCV applies it: the two would disagree on every image's size. Here each
photo is decoded once with the tag applied (`cv2.imread`'s default), downscaled with area averaging so its
longer side is at most `max_size`, and written without EXIF (a JPEG as JPEG, a PNG as PNG), so every later
reader sees the same upright pixels. A video's frames are decoded by the FFmpeg the imageio-ffmpeg wheel
ships (which applies the video's rotation), and from each of `frames` equal stretches of it the sharpest
frame is kept (the variance of its Laplacian: motion blur smooths it away), as capture apps do.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.base.progress import Progress
from engine.formats.checks import check_pixels

PHOTO_TYPES = {".jpg", ".jpeg", ".png", ".tif", ".tiff", ".bmp", ".webp"}
JPEG_QUALITY = 95


def photo_files(folder: Path) -> list[Path]:
    """The images in `folder` (not below it), sorted by name; refused when there are fewer than three."""
    if not folder.is_dir():
        raise InputError(f"{folder} is not a folder of photos: name the folder that holds your images")
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in PHOTO_TYPES and p.is_file())
    if len(files) < 3:
        raise InputError(f"{folder} holds {len(files)} images ({', '.join(sorted(PHOTO_TYPES))}): SfM needs at "
                         "least 3 overlapping photos, dozens for a scene")
    return files


def fit(image: np.ndarray, max_size: int) -> np.ndarray:
    """`image` downscaled (area averaging) so its longer side is at most `max_size`; unchanged when it is."""
    h, w = image.shape[:2]
    scale = max_size / max(h, w)
    if max_size <= 0 or scale >= 1:
        return image
    return cv2.resize(image, (max(1, round(w * scale)), max(1, round(h * scale))), interpolation=cv2.INTER_AREA)


def write_image(path: Path, bgr: np.ndarray) -> None:
    """A JPEG (quality JPEG_QUALITY) or a lossless PNG, by `path`'s suffix, written beside its name and renamed:
    a stopped capture never leaves half an image."""
    flags = [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY] if path.suffix == ".jpg" else []
    ok, data = cv2.imencode(path.suffix, bgr, flags)
    if not ok:
        raise InputError(f"could not encode {path.name}")
    partial = path.with_name(f".{path.name}.part")
    partial.write_bytes(data.tobytes())
    os.replace(partial, path)


def prepare_photos(files: list[Path], out: Path, max_size: int) -> list[str]:
    """Each photo upright and fitted into `out` as NAME.jpg, or NAME.png for a PNG (kept lossless), photos already
    there kept (a stopped capture continues); returns the names written, in order."""
    out.mkdir(parents=True, exist_ok=True)
    names, progress = [], Progress("photos", len(files))
    stems = [f.stem for f in files]
    if len(set(stems)) < len(stems):
        raise InputError(f"{files[0].parent} holds photos that differ only in their extension: rename them")
    for k, path in enumerate(files):
        name = path.stem + (".png" if path.suffix.lower() == ".png" else ".jpg")
        if not (out / name).is_file():
            image = cv2.imread(str(path), cv2.IMREAD_COLOR)  # applies the EXIF orientation
            if image is None:
                raise InputError(f"{path} is not an image OpenCV can read: convert it to JPEG or PNG, or remove it")
            check_pixels(image.shape[1], image.shape[0], path)
            write_image(out / name, fit(image, max_size))
        names.append(name)
        progress.update(k + 1)
    progress.close()
    return names


def sharpness(gray: np.ndarray) -> float:
    """Variance of the Laplacian: high for a crisp frame, low for a blurred one."""
    return float(cv2.Laplacian(gray, cv2.CV_32F).var())


def video_frames(path: Path) -> tuple[Iterator[np.ndarray], int]:
    """The video's frames as RGB arrays (rotation applied) and their count (FFmpeg's, exact)."""
    try:
        import imageio_ffmpeg
    except ImportError as exc:
        raise InputError("reading a video needs imageio-ffmpeg: pip install imageio-ffmpeg "
                         "(requirements/engine.txt), or extract its frames and pass --images") from exc
    if not path.is_file():
        raise InputError(f"{path} missing: name the video file to take frames from")
    try:
        count = imageio_ffmpeg.count_frames_and_secs(str(path))[0]
        reader = imageio_ffmpeg.read_frames(str(path))
        meta = next(reader)
    except (RuntimeError, OSError, StopIteration) as exc:
        raise InputError(f"{path} is not a video FFmpeg can decode ({str(exc).splitlines()[0][:120]}): "
                         "convert it to MP4") from exc
    w, h = meta["size"]
    if meta.get("rotate", 0) in (90, 270):
        w, h = h, w

    def frames() -> Iterator[np.ndarray]:
        for raw in reader:
            yield np.frombuffer(raw, np.uint8).reshape(h, w, 3)

    return frames(), count


def prepare_video(path: Path, out: Path, frames: int, max_size: int) -> list[str]:
    """The sharpest frame of each of `frames` equal stretches of the video, fitted, as frame_NNNNN.jpg in `out`
    (a stopped capture decodes again: the choice is the same); returns the names in time order."""
    decoded, count = video_frames(path)
    if count < 3:
        raise InputError(f"{path} has {count} frames: SfM needs at least 3 views")
    stretches = min(frames, count)
    best: dict[int, tuple[float, int, np.ndarray]] = {}
    progress = Progress("frames", count)
    for k, rgb in enumerate(decoded):
        stretch = min(k * stretches // count, stretches - 1)
        small = fit(rgb, max_size)
        score = sharpness(cv2.cvtColor(small, cv2.COLOR_RGB2GRAY))
        if stretch not in best or score > best[stretch][0]:
            best[stretch] = (score, k, small)
        if k % 10 == 0:
            progress.update(k + 1)
    progress.close()
    out.mkdir(parents=True, exist_ok=True)
    names = []
    for _, k, rgb in (best[s] for s in sorted(best)):
        name = f"frame_{k:05d}.jpg"
        if not (out / name).is_file():
            write_image(out / name, cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))
        names.append(name)
    return names
