"""Frames (PNGs) into an H.264 MP4 with the FFmpeg that the `imageio-ffmpeg` wheel ships (no system FFmpeg).

Why this package: it is on the registry with an FFmpeg build inside (libx264 included), so a clean set-up
can write the turntables people look at. Frames are fed as raw RGB through a pipe (any file names, in sorted
order), padded to even sizes with black (yuv420p needs them), and the file is written beside its final name
and renamed when complete; it is then decoded again (OpenCV) and its frames counted, so a file that does not
play is an error here rather than a surprise later.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.io.image_io import read_png

FFMPEG_MISSING = ("imageio-ffmpeg is not installed: pip install imageio-ffmpeg (requirements/engine.txt); it "
                  "ships the FFmpeg the MP4 is written with")


def ffmpeg_exe() -> str:
    try:
        import imageio_ffmpeg
    except ImportError as exc:
        raise InputError(FFMPEG_MISSING) from exc
    return imageio_ffmpeg.get_ffmpeg_exe()


def has_ffmpeg() -> bool:
    try:
        import imageio_ffmpeg  # noqa: F401
    except ImportError:
        return False
    return True


def _even(image: np.ndarray) -> np.ndarray:
    h, w = image.shape[:2]
    return np.pad(image, ((0, h % 2), (0, w % 2), (0, 0)))


def count_frames(path: Path) -> int:
    """Frames in a video, by decoding every one (OpenCV's FFmpeg back end)."""
    capture = cv2.VideoCapture(str(path))
    count = 0
    while capture.read()[0]:
        count += 1
    capture.release()
    return count


def write_mp4(frames: list[Path], out: Path, fps: int = 24, crf: int = 20) -> Path:
    """Write `frames` (same size) to `out` as H.264 (yuv420p, `crf` quality), then check it decodes to as many
    frames."""
    if not frames:
        raise InputError("no frames to write: the folder holds no PNG")
    first = _even(read_png(frames[0]))
    h, w = first.shape[:2]
    tmp = out.with_name(f".{out.stem}.partial{out.suffix}")
    out.parent.mkdir(parents=True, exist_ok=True)
    if not has_ffmpeg():
        _write_opencv(frames, tmp, fps, (w, h))
    else:
        _write_h264(frames, tmp, fps, crf, (w, h))
    decoded = count_frames(tmp)
    if decoded != len(frames):
        tmp.unlink(missing_ok=True)
        raise InputError(f"{out} decodes to {decoded} frames, not {len(frames)}: not written")
    tmp.replace(out)
    return out


def _frames(frames: list[Path], size: tuple[int, int]):
    w, h = size
    for path in frames:
        image = _even(read_png(path))
        if image.shape[:2] != (h, w):
            raise InputError(f"{path} is {image.shape[1]}x{image.shape[0]}, the first frame {w}x{h}: frames of "
                             "one video must share a size")
        yield image


def _write_opencv(frames: list[Path], tmp: Path, fps: int, size: tuple[int, int]) -> None:
    """MPEG-4 Part 2 through OpenCV's own FFmpeg: where imageio-ffmpeg is absent (a machine with only
    opencv-python), a turntable is still written, in a codec fewer browsers play than H.264."""
    writer = cv2.VideoWriter(str(tmp), cv2.VideoWriter_fourcc(*"mp4v"), fps, size)
    if not writer.isOpened():
        raise InputError(FFMPEG_MISSING)
    try:
        for image in _frames(frames, size):
            writer.write(np.ascontiguousarray(image[..., ::-1]))
    finally:
        writer.release()


def _write_h264(frames: list[Path], tmp: Path, fps: int, crf: int, size: tuple[int, int]) -> None:
    w, h = size
    command = [ffmpeg_exe(), "-y", "-loglevel", "error", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w}x{h}",
               "-framerate", str(fps), "-i", "-", "-c:v", "libx264", "-crf", str(crf), "-pix_fmt", "yuv420p",
               "-movflags", "+faststart", str(tmp)]
    process = subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        for image in _frames(frames, size):
            process.stdin.write(np.ascontiguousarray(image).tobytes())
    finally:
        process.stdin.close()
        error = process.stderr.read().decode(errors="replace").strip()
        process.wait()
    if process.returncode != 0:
        tmp.unlink(missing_ok=True)
        said = error.splitlines()[-1] if error else process.returncode
        raise InputError(f"FFmpeg could not write {tmp.name}: {said}")
