"""A user's capture: lens distortion undistorted, large images downscaled, both into a cache, never into it."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from engine.base.errors import InputError
from engine.capture.scene import load_scene

W, H, F, CX, CY = 96, 72, 80.0, 48.0, 36.0


def texture(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """A smooth colour pattern over normalised (undistorted) image coordinates."""
    return np.stack([128 + 100 * np.sin(14 * x), 128 + 100 * np.cos(12 * y), 128 + 80 * np.sin(9 * (x + y))], -1)


def radial_image(k: float) -> np.ndarray:
    """What a SIMPLE_RADIAL camera (f, cx, cy, k) sees of the texture: each pixel's undistorted coordinates
    found by fixed-point iteration of COLMAP's x_d = x (1 + k r^2)."""
    v, u = np.mgrid[0:H, 0:W] + 0.5
    xd, yd = (u - CX) / F, (v - CY) / F
    x, y = xd.copy(), yd.copy()
    for _ in range(50):
        r2 = x * x + y * y
        x, y = xd / (1 + k * r2), yd / (1 + k * r2)
    return np.clip(texture(x, y), 0, 255).astype(np.uint8)


def write_capture(root: Path, model: str, params: str, image: np.ndarray) -> None:
    """A text COLMAP model (as a capture app exports it) with three views of the same camera."""
    (root / "sparse" / "0").mkdir(parents=True)
    (root / "images").mkdir()
    (root / "sparse" / "0" / "cameras.txt").write_text(f"# a capture\n1 {model} {W} {H} {params}\n")
    lines = []
    for k in range(3):
        lines += [f"{k + 1} 1 0 0 0 {0.1 * k} 0 4 1 {k:04d}.png", ""]
        cv2.imwrite(str(root / "images" / f"{k:04d}.png"), image[..., ::-1])
    (root / "sparse" / "0" / "images.txt").write_text("\n".join(lines) + "\n")
    (root / "sparse" / "0" / "points3D.txt").write_text("1 0 0 1 200 100 50 0.1\n2 0.2 0.1 1.5 50 60 70 0.1\n")


@pytest.mark.parametrize("model, params", [("SIMPLE_RADIAL", f"{F} {CX} {CY} -0.25"),
                                           ("RADIAL", f"{F} {CX} {CY} -0.25 0"),
                                           ("OPENCV", f"{F} {F} {CX} {CY} -0.25 0 0 0")])
def test_a_distorted_capture_loads_undistorted_and_matches_the_pinhole_view(tmp_path: Path, monkeypatch, model,
                                                                            params):
    monkeypatch.setenv("SPLATFILL_CACHE", str(tmp_path / "cache"))
    root = tmp_path / "capture"
    write_capture(root, model, params, radial_image(-0.25))
    before = sorted(p.relative_to(root) for p in root.rglob("*"))
    scene = load_scene(root)
    assert scene.root.parent == tmp_path / "cache" and len(scene.cameras) == 3
    assert sorted(p.relative_to(root) for p in root.rglob("*")) == before  # nothing written into the capture
    cam = scene.cameras[0]
    v, u = np.mgrid[0:cam.height, 0:cam.width] + 0.5
    expected = np.clip(texture((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy), 0, 255)
    inner = (slice(4, -4), slice(4, -4))  # borders interpolate against blank pixels
    error = np.abs(scene.images[0].astype(float) - expected)[inner].mean()  # the distorted image itself: 10.8
    assert error < 2.0, f"mean error {error:.2f} / 255 against the exact pinhole view (measured 0.5)"
    assert load_scene(root).root == scene.root  # the cache is reused


def test_fisheye_is_refused_with_the_fix(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("SPLATFILL_CACHE", str(tmp_path / "cache"))
    fisheye = tmp_path / "fisheye"
    write_capture(fisheye, "OPENCV_FISHEYE", f"{F} {F} {CX} {CY} 0 0 0 0", radial_image(0.0))
    with pytest.raises(InputError, match="OPENCV_FISHEYE cameras, which splatfill cannot undistort"):
        load_scene(fisheye)


@pytest.mark.parametrize("model, params", [("SIMPLE_RADIAL", f"{F} {CX} {CY} -0.25"),
                                           ("OPENCV", f"{F} {F} {CX} {CY} -0.25 0 0.002 -0.001")])
def test_folders_aligned_with_distorted_images_are_undistorted_with_them(tmp_path: Path, monkeypatch, model,
                                                                         params):
    """masks/ (ids, nearest) and gt/ (colours, bilinear) land where pycolmap put the images: before, such a
    capture was refused (a generator's scene through SfM keeps its gt/ for scoring)."""
    monkeypatch.setenv("SPLATFILL_CACHE", str(tmp_path / "cache"))
    root = tmp_path / "capture"
    image = radial_image(-0.25)
    write_capture(root, model, params, image)
    (root / "masks").mkdir()
    (root / "gt").mkdir()
    for k in range(3):
        cv2.imwrite(str(root / "masks" / f"{k:04d}.png"), np.where(image[..., 0] > 128, 5, 0).astype(np.uint8))
        cv2.imwrite(str(root / "gt" / f"{k:04d}.png"), image[..., ::-1])
    scene = load_scene(root)
    inner = (slice(4, -4), slice(4, -4))
    gt_error = np.abs(scene.gt_images[0].astype(float) - scene.images[0])[inner].mean()
    assert gt_error < 1.0, f"gt/ against pycolmap's undistorted image: {gt_error:.2f} / 255"
    assert set(np.unique(scene.masks[0])) <= {0, 5}
    agree = (scene.masks[0] == 5) == (scene.images[0][..., 0] > 128)
    assert agree[inner].mean() > 0.97


def test_resolution_loads_the_scene_at_a_fraction_with_consistent_cameras(tmp_path: Path, monkeypatch):
    """As 3DGS's -r 2: half the pixels, intrinsics scaled with them, masks resized without blending ids."""
    from engine.formats.cameras import project

    monkeypatch.setenv("SPLATFILL_CACHE", str(tmp_path / "cache"))
    root = tmp_path / "capture"
    write_capture(root, "PINHOLE", f"{F} {F} {CX} {CY}", radial_image(0.0))
    (root / "masks").mkdir()
    ids = np.zeros((H, W), np.uint8)
    ids[10:40, 20:60] = 3
    for k in range(3):
        cv2.imwrite(str(root / "masks" / f"{k:04d}.png"), ids)
    full, half = load_scene(root), load_scene(root, resolution=2)
    assert half.root.parent == tmp_path / "cache" and not (root / "sparse" / "0" / "cameras.bin").exists()
    cam = half.cameras[0]
    assert (cam.width, cam.height) == (W // 2, H // 2) and half.images[0].shape == (H // 2, W // 2, 3)
    point = np.array([[0.3, -0.2, 5.0]])
    u, v, _ = project(full.cameras[0], point)
    u2, v2, _ = project(cam, point)
    assert np.allclose([u2[0], v2[0]], [u[0] / 2, v[0] / 2])
    assert set(np.unique(half.masks[0])) == {0, 3} and (half.masks[0] == 3).sum() == (ids == 3).sum() // 4
    expected = cv2.resize(full.images[0], (W // 2, H // 2), interpolation=cv2.INTER_AREA)
    assert np.array_equal(half.images[0], expected)
    with pytest.raises(InputError, match="--resolution 3 unknown"):
        load_scene(root, resolution=3)
