"""Re-running COLMAP on a completion's training images (the paper's ablation): a textured two-plane scene
rendered exactly from known cameras, so the re-estimated poses and points can be checked against the truth."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from engine.base.errors import InputError
from engine.capture.scene import load_scene
from engine.complete.recolmap import rerun_colmap, umeyama
from engine.formats.cameras import Camera
from engine.io.colmap_model import ColmapModel, write_model
from engine.io.image_io import write_png

# (origin, edge 1, edge 2) of two textured rectangles: a wall at x = -2 and the ground z = 0
PLANES = [(np.array([-2.0, -2, 0]), np.array([0, 4.0, 0]), np.array([0, 0, 2.5])),
          (np.array([-2.0, -2, 0]), np.array([4.0, 0, 0]), np.array([0, 4.0, 0]))]


def _look_at(center: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    z = -center / np.linalg.norm(center)
    x = np.cross(z, [0, 0, 1.0])
    x /= np.linalg.norm(x)
    rotation = np.stack([x, np.cross(z, x), z])
    return rotation, -rotation @ center


def _texture(rng: np.random.Generator, size: int = 512) -> np.ndarray:
    """Noise at six scales: features for SIFT at every size."""
    tex = sum(cv2.resize(rng.random((n, n, 3)).astype(np.float32), (size, size), interpolation=cv2.INTER_CUBIC)
              for n in (4, 8, 16, 32, 64, 128))
    return (255 * (tex - tex.min()) / np.ptp(tex)).astype(np.uint8)


def make_planes_scene(root: Path, views: int = 12, flat: bool = False) -> list[Camera]:
    """Views on a 60-degree arc, each plane warped in by its exact homography (the wall drawn first: the
    ground is in front of it from every view). `flat`: untextured planes, which no feature matcher can use."""
    rng = np.random.default_rng(0)
    textures = [np.full((512, 512, 3), 120 + 40 * k, np.uint8) if flat else _texture(rng) for k in range(2)]
    cameras = []
    for k in range(views):
        angle = np.radians(-30 + 60 * k / (views - 1))
        rotation, t = _look_at(np.array([4 * np.cos(angle), 4 * np.sin(angle), 2.0]))
        cameras.append(Camera(name=f"{k:04d}.png", width=320, height=240, fx=250.0, fy=250.0, cx=160.0,
                              cy=120.0, R=rotation, t=t))
    for camera in cameras:
        image = np.full((240, 320, 3), 90, np.uint8)
        K = np.array([[camera.fx, 0, camera.cx], [0, camera.fy, camera.cy], [0, 0, 1]])
        for (origin, e1, e2), tex in zip(PLANES, textures, strict=True):
            n = tex.shape[0]
            H = K @ np.column_stack([camera.R @ e1 / n, camera.R @ e2 / n, camera.R @ origin + camera.t])
            cover = cv2.warpPerspective(np.full((n, n), 255, np.uint8), H, (320, 240)) > 127
            image[cover] = cv2.warpPerspective(tex, H, (320, 240))[cover]
        write_png(root / "images" / camera.name, image)
    points = np.concatenate([o + rng.random((50, 1)) * e1 + rng.random((50, 1)) * e2 for o, e1, e2 in PLANES])
    write_model(root / "sparse" / "0", ColmapModel(cameras, points, np.full((len(points), 3), 128, np.uint8)))
    names = [c.name for c in cameras]
    (root / "split.json").write_text(json.dumps({"train": [n for k, n in enumerate(names) if k % 4],
                                                 "test": names[::4]}))
    return cameras


def test_umeyama_recovers_a_similarity():
    rng = np.random.default_rng(1)
    points = rng.normal(size=(20, 3))
    rotation = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    rotation *= np.sign(np.linalg.det(rotation))
    found = umeyama(points, 2.5 * points @ rotation.T + [1.0, -2.0, 0.5])
    assert found.scale == pytest.approx(2.5) and np.allclose(found.rotation, rotation)
    assert np.allclose(found.shift, [1.0, -2.0, 0.5])


def test_recolmap_reestimates_training_poses_and_keeps_test_cameras(tmp_path: Path):
    truth = make_planes_scene(tmp_path)
    train = json.loads((tmp_path / "split.json").read_text())["train"]
    report = rerun_colmap(tmp_path, train, tmp_path / "colmap")
    assert report["registered"] == 9 and not report["dropped"]
    assert report["mean_centre_error_of_extent"] < 0.01 and report["mean_rotation_error_deg"] < 1.0
    scene = load_scene(tmp_path)  # the rewritten model loads as a scene
    by_name = {c.name: c for c in truth}
    for i in scene.test:  # test views keep their original poses (to the model files' rounding)
        assert np.allclose(scene.cameras[i].R, by_name[scene.cameras[i].name].R, atol=1e-12)
    for i in scene.train:  # training views: re-estimated, close to the truth, but not copied from it
        camera, original = scene.cameras[i], by_name[scene.cameras[i].name]
        assert 0 < np.linalg.norm(camera.center - original.center) < 0.05
    on_a_plane = (np.abs(scene.points[:, 0] + 2) < 0.05) | (np.abs(scene.points[:, 2]) < 0.05)
    assert len(scene.points) > 300 and on_a_plane.mean() > 0.9  # new points, on the true surfaces


def test_recolmap_without_features_names_the_folder_and_the_fix(tmp_path: Path):
    make_planes_scene(tmp_path, flat=True)
    train = json.loads((tmp_path / "split.json").read_text())["train"]
    with pytest.raises(InputError, match="without --recolmap"):
        rerun_colmap(tmp_path, train, tmp_path / "colmap")
