"""Turntable videos: PNG frames into an H.264 MP4 with the FFmpeg the imageio-ffmpeg wheel ships, checked by
decoding the file again."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from engine.cli import main
from engine.io.image_io import write_png
from engine.pictures.video import count_frames


def frames(folder: Path, count: int, size: tuple[int, int] = (51, 77)) -> Path:
    """Odd-sized frames (yuv420p needs even ones: the writer pads), a white bar moving right."""
    for k in range(count):
        image = np.zeros((*size, 3), np.uint8)
        image[10:30, 6 * k:6 * k + 12] = 255
        write_png(folder / f"{k:04d}.png", image)
    return folder


def test_frames_become_an_mp4_that_decodes_to_every_frame(tmp_path: Path):
    out = tmp_path / "tt.mp4"
    assert main(["video", "--frames", str(frames(tmp_path / "f", 12)), "--out", str(out), "--fps", "12"]) == 0
    assert count_frames(out) == 12
    capture = cv2.VideoCapture(str(out))
    capture.read()
    ok, second = capture.read()
    assert ok and second.shape == (52, 78, 3)  # padded to even
    assert second[20, 6:18].mean() > 200 and second[20, 40:60].mean() < 40  # the bar where frame 1 drew it
    assert not list(tmp_path.glob(".*partial*"))  # nothing half-written left beside it


def test_bad_frames_and_an_existing_file_are_refused_with_one_line(tmp_path: Path, capsys):
    folder = frames(tmp_path / "f", 2)
    write_png(folder / "0009.png", np.zeros((20, 20, 3), np.uint8))
    assert main(["video", "--frames", str(folder), "--out", str(tmp_path / "a.mp4")]) == 2
    assert "must share a size" in capsys.readouterr().err and not (tmp_path / "a.mp4").exists()
    assert main(["video", "--frames", str(tmp_path / "none"), "--out", str(tmp_path / "b.mp4")]) == 2
    assert "no frames" in capsys.readouterr().err
    (tmp_path / "c.mp4").write_bytes(b"x")
    assert main(["video", "--frames", str(folder), "--out", str(tmp_path / "c.mp4")]) == 2
    assert (tmp_path / "c.mp4").read_bytes() == b"x"


def test_a_single_frame_is_a_video_too(tmp_path: Path):
    out = tmp_path / "one.mp4"
    assert main(["video", "--frames", str(frames(tmp_path / "f", 1)), "--out", str(out)]) == 0
    assert count_frames(out) == 1


def test_without_imageio_ffmpeg_opencv_writes_the_mp4(tmp_path: Path, monkeypatch):
    """A machine with only opencv-python (the GPU machine has no imageio-ffmpeg): MPEG-4 Part 2 through
    OpenCV's FFmpeg, the same frames decoded again."""
    from engine.pictures import video

    monkeypatch.setattr(video, "has_ffmpeg", lambda: False)
    out = video.write_mp4(sorted(frames(tmp_path / "f", 10).glob("*.png")), tmp_path / "cv.mp4", 10)
    assert count_frames(out) == 10
    capture = cv2.VideoCapture(str(out))
    capture.read()
    ok, second = capture.read()
    assert ok and second[20, 6:18].mean() > 180 and second[20, 40:60].mean() < 60
