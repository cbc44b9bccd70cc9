"""Photos and video frames as `capture` prepares them for SfM: upright, fitted, the sharpest frames (the SfM
itself runs in tests/capture/test_user_path.py, on the README's commands)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from engine.base.errors import InputError
from engine.capture.photos import photo_files, prepare_photos, prepare_video
from tests.capture.test_user_path import SIDE, exif_jpeg


def scene_picture(h: int = 120, w: int = 200) -> np.ndarray:
    """A landscape picture whose top-left corner is white: which way up it is shows."""
    rng = np.random.default_rng(0)
    image = rng.integers(0, 120, (h, w, 3)).astype(np.uint8)
    image[:20, :30] = 255
    return image


def test_photos_come_out_upright_fitted_and_without_exif(tmp_path: Path):
    photos, out = tmp_path / "photos", tmp_path / "out"
    photos.mkdir()
    picture = scene_picture()
    for k, orientation in enumerate((1, 6, 8)):
        stored = cv2.rotate(picture, SIDE[orientation]) if orientation != 1 else picture
        (photos / f"IMG_{k}.jpg").write_bytes(exif_jpeg(stored, orientation))
    cv2.imwrite(str(photos / "scan.png"), picture)
    names = prepare_photos(photo_files(photos), out, max_size=100)
    assert names == ["IMG_0.jpg", "IMG_1.jpg", "IMG_2.jpg", "scan.png"]  # a PNG stays lossless
    for name in names:
        image = cv2.imread(str(out / name), cv2.IMREAD_IGNORE_ORIENTATION | cv2.IMREAD_COLOR)
        assert image.shape == (60, 100, 3), name  # upright in its stored pixels, longer side 100
        assert image[:8, :12].mean() > 200 and image[-20:, -20:].mean() < 130, name
    assert prepare_photos(photo_files(photos), out, max_size=100) == names  # kept, not redone


def test_too_few_photos_or_an_unreadable_one_are_refused_with_one_line(tmp_path: Path):
    (tmp_path / "a.jpg").write_bytes(b"not a jpeg")
    with pytest.raises(InputError, match="at least 3"):
        photo_files(tmp_path)
    for k in range(3):
        (tmp_path / f"b{k}.jpg").write_bytes(b"not a jpeg")
    with pytest.raises(InputError, match="not an image OpenCV can read"):
        prepare_photos(photo_files(tmp_path), tmp_path / "out", 100)


def test_a_video_gives_the_sharpest_frame_of_each_stretch(tmp_path: Path):
    """Ten frames, every other one blurred as a shaking hand blurs it: five stretches of two keep the five
    sharp ones."""
    from engine.pictures.video import write_mp4

    frames = []
    for k in range(10):
        image = scene_picture(96, 128)
        image = cv2.GaussianBlur(image, (9, 9), 4) if k % 2 else image
        path = tmp_path / "frames" / f"{k:02d}.png"
        path.parent.mkdir(exist_ok=True)
        cv2.imwrite(str(path), image)
        frames.append(path)
    video = write_mp4(frames, tmp_path / "clip.mp4", fps=10)
    names = prepare_video(video, tmp_path / "out", frames=5, max_size=0)
    assert names == [f"frame_{k:05d}.jpg" for k in (0, 2, 4, 6, 8)]
    assert cv2.imread(str(tmp_path / "out" / names[0])).shape == (96, 128, 3)
