"""Loading scene folders: every broken input ends with one line naming the file; nothing loads half."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from engine.base.errors import InputError
from engine.capture.scene import load_scene

REPO = Path(__file__).resolve().parents[2]


def _truncate(path: Path, keep: int) -> None:
    path.write_bytes(path.read_bytes()[:keep])


BREAKAGES = {
    # name: (what to do to the copied scene, the path the error must name)
    "no_model": (lambda s: shutil.rmtree(s / "sparse"), "sparse"),
    "no_images_bin": (lambda s: (s / "sparse/0/images.bin").unlink(), "images.bin"),
    "truncated_cameras_bin": (lambda s: _truncate(s / "sparse/0/cameras.bin", 4), "cameras.bin"),
    "corrupt_images_bin": (lambda s: _truncate(s / "sparse/0/images.bin", 40), "images.bin"),
    "truncated_points_bin": (lambda s: _truncate(s / "sparse/0/points3D.bin", 5000), "points3D.bin"),
    "missing_image": (lambda s: (s / "images/0003.png").unlink(), "images/0003.png"),
    "corrupt_image": (lambda s: (s / "images/0002.png").write_bytes(b"not a png"), "images/0002.png"),
    "truncated_image": (lambda s: _truncate(s / "images/0001.png", 60), "images/0001.png"),
    "missing_mask": (lambda s: (s / "masks/0004.png").unlink(), "masks/0004.png"),
    "wrong_size_mask": (lambda s: shutil.copy(REPO / "tests" / "data" / "mask_8x8.png", s / "masks/0000.png"),
                        "masks/0000.png"),
    "missing_depth": (lambda s: (s / "depth/0006.exr").unlink(), "depth/0006.exr"),
    "corrupt_depth": (lambda s: _truncate(s / "depth/0006.exr", 100), "depth/0006.exr"),
    "bad_split_json": (lambda s: (s / "split.json").write_text("{train: "), "split.json"),
    "split_names_unknown_view": (lambda s: (s / "split.json").write_text('{"train": ["x.png"], "test": []}'),
                                 "split.json"),
    "bad_objects_json": (lambda s: (s / "masks/objects.json").write_text('[{"id": 1}]'), "objects.json"),
    "missing_test_gt": (lambda s: (s / "gt/0005.png").unlink(), "gt"),
}


@pytest.fixture
def scene_copy(living_scene: Path, tmp_path: Path) -> Path:
    return Path(shutil.copytree(living_scene, tmp_path / "scene"))


def test_a_good_scene_loads_completely(living_scene: Path):
    scene = load_scene(living_scene, depth=True)
    n = len(scene.cameras)
    assert len(scene.images) == len(scene.masks) == len(scene.depths) == n == 8
    assert scene.test == [5] and len(scene.train) == 7
    assert len(scene.gt_images) == len(scene.gt_depths) == len(scene.holes) == n
    assert scene.target.name == "plush" and scene.object_by("plush") is scene.object_by(scene.target.id)
    assert scene.images[0].shape == (72, 96, 3) and scene.depths[0].dtype == np.float32


@pytest.mark.parametrize("breakage", sorted(BREAKAGES))
def test_broken_input_names_the_file(scene_copy: Path, breakage: str):
    break_it, named = BREAKAGES[breakage]
    break_it(scene_copy)
    with pytest.raises(InputError) as info:
        load_scene(scene_copy, depth=True)
    message = str(info.value)
    assert named in message and "\n" not in message


def test_unknown_object_lists_the_objects_present(living_scene: Path):
    with pytest.raises(InputError, match=r"objects present: 1=plush, 2=box"):
        load_scene(living_scene).object_by("teapot")


def test_a_plain_colmap_folder_loads_with_a_default_split(scene_copy: Path):
    for extra in ("masks", "depth", "gt", "gt_depth", "holes", "unseen", "split.json", "scene.json"):
        path = scene_copy / extra
        shutil.rmtree(path) if path.is_dir() else path.unlink()
    scene = load_scene(scene_copy, depth=True)
    assert scene.masks is None and scene.depths is None and not scene.gt_images
    assert scene.test == [0] and scene.train == list(range(1, 8))  # every 8th view, as 3DGS does


def test_the_numpy_reader_agrees_with_pycolmap_on_binary_and_text_models(living_scene: Path, tmp_path: Path):
    import zlib  # noqa: F401,I001  -- before pycolmap
    import pycolmap

    from engine.io.colmap_model import read_model

    rec = pycolmap.Reconstruction(str(living_scene / "sparse" / "0"))
    rec.write_text(str(tmp_path))
    for model in (read_model(living_scene / "sparse" / "0"), read_model(tmp_path)):
        for cam in model.cameras:
            image = rec.find_image_with_name(cam.name)
            pose = image.cam_from_world()
            assert np.allclose(cam.R, pose.rotation.matrix(), atol=1e-6) and np.allclose(cam.t, pose.translation)
            assert [cam.fx, cam.fy, cam.cx, cam.cy] == pytest.approx(list(rec.cameras[image.camera_id].params))
        ids = sorted(rec.points3D)
        assert np.allclose(model.points, [rec.points3D[i].xyz for i in ids], atol=1e-6)
        assert np.array_equal(model.colors, [rec.points3D[i].color for i in ids])


def test_cli_reports_one_line_and_status_2(scene_copy: Path):
    (scene_copy / "images/0003.png").unlink()
    proc = subprocess.run([sys.executable, "-m", "engine", "info", "--scene", str(scene_copy)],
                          capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "images/0003.png" in proc.stderr


def test_png_writes_after_loading_a_colmap_model(living_scene: Path, tmp_path: Path):
    """pycolmap 4.2.1 aborts the next zlib compression unless zlib loaded first: guard the import order."""
    code = (f"from engine.capture.scene import load_scene; load_scene({str(living_scene)!r}); "
            f"import numpy as np, cv2; assert cv2.imwrite({str(tmp_path / 'x.png')!r}, np.zeros((4, 4), np.uint8)); "
            f"np.savez_compressed({str(tmp_path / 'y.npz')!r}, a=np.zeros(3))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 0, proc.stderr[-500:]


@pytest.mark.fast
def test_a_view_named_after_a_jpeg_photo_is_written_as_png_and_reads_back_exactly(tmp_path: Path):
    """A capture's views are named IMG_0001.jpg and every stage names its files after them: a hole mask written
    as JPEG came back with its edge grown by ringing (40% more pixels in the README path's IMG_0005)."""
    from engine.io.image_io import read_png, write_png

    rng = np.random.default_rng(0)
    mask = np.zeros((48, 64), np.uint8)
    mask[10:30, 20:45] = 255
    rgb = rng.integers(0, 256, (48, 64, 3), dtype=np.uint8)
    write_png(tmp_path / "holes" / "IMG_0001.jpg", mask)
    write_png(tmp_path / "images" / "IMG_0001.jpg", rgb)
    assert (tmp_path / "holes" / "IMG_0001.jpg").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.array_equal(read_png(tmp_path / "holes" / "IMG_0001.jpg", "mask", (64, 48)), mask)
    assert np.array_equal(read_png(tmp_path / "images" / "IMG_0001.jpg", size=(64, 48)), rgb)


def test_objects_json_round_trips(living_scene: Path):
    entries = json.loads((living_scene / "masks/objects.json").read_text())
    assert sum(e["target"] for e in entries) == 1 and {e["id"] for e in entries} == set(range(1, 6))
