"""The generator's scene folders: COLMAP model, camera conventions, masks, ground truth, determinism."""

from __future__ import annotations

import json
import zlib  # noqa: F401,I001  -- before pycolmap, see engine/io/colmap_model.py
from pathlib import Path

import cv2  # noqa: F401
import numpy as np
import pycolmap
import pytest
from conftest import make_scene

from engine.capture.scene import load_scene
from engine.formats.cameras import backproject, pixel_grid, project

FOLDERS = ["images", "gt", "masks", "depth", "gt_depth", "holes"]


def test_colmap_model_reads_back_through_pycolmap_and_names_match_the_image_folders(any_scene: Path):
    rec = pycolmap.Reconstruction(str(any_scene / "sparse" / "0"))
    names = sorted(image.name for image in rec.images.values())
    assert names == sorted(p.name for p in (any_scene / "images").glob("*.png"))
    for folder in FOLDERS:
        stems = sorted(p.stem for p in (any_scene / folder).iterdir() if p.suffix in (".png", ".exr"))
        assert stems == [Path(n).stem for n in names], folder
    assert all(cam.model.name == "PINHOLE" for cam in rec.cameras.values())
    assert rec.num_points3D() > 1000
    assert rec.compute_mean_track_length() > 1.5  # points carry real observations, not bare xyz


def _bilinear(image: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """image at pixel coordinates (u, v) (COLMAP: pixel centres at +0.5); -1 outside."""
    return cv2.remap(image, (u - 0.5).astype(np.float32)[None], (v - 0.5).astype(np.float32)[None],
                     cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=-1.0)[0]


def test_back_projected_depth_lands_on_the_other_views_depth(living_scene: Path):
    """Pins every convention at once: intrinsics, pose direction, axes, pixel centres, z-depth.

    Measured on the tiny livingroom scene: median relative error about 1e-4; shifting the second
    camera's principal point by half a pixel raises it to about 1e-2.
    """
    scene = load_scene(living_scene, depth=True)
    checked = 0
    for a, b in [(0, 1), (1, 2), (0, 3), (4, 6)]:
        cam_a, cam_b = scene.cameras[a], scene.cameras[b]
        u, v = pixel_grid(cam_a)
        depth_a = scene.depths[a]
        keep = np.isfinite(depth_a) & (depth_a < 5.0)  # the dome is far and flat: uninformative
        points = backproject(cam_a, u[keep], v[keep], depth_a[keep])
        ub, vb, zb = project(cam_b, points)
        surface = _bilinear(np.nan_to_num(scene.depths[b], posinf=1e3), ub, vb)
        inside = (surface > 0) & (zb > 0)
        rel = (zb[inside] - surface[inside]) / surface[inside]
        assert np.median(np.abs(rel)) < 2e-3, (a, b)
        assert (np.abs(rel) < 0.01).mean() > 0.5, (a, b)  # the rest is occluded in B or at edges
        checked += inside.sum()
    assert checked > 10_000


def test_target_mask_covers_where_images_and_gt_differ_shadows_aside(any_scene: Path):
    scene = load_scene(any_scene)
    target = scene.target.id
    for i, gt in scene.gt_images.items():
        mask = cv2.dilate((scene.masks[i] == target).astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
        diff = scene.images[i].astype(int) - gt.astype(int)
        changed = np.abs(diff).max(axis=-1) > 40
        brighter = diff.mean(axis=-1) > 10  # the object's shadow only darkens
        outside = changed & ~mask & brighter
        assert outside.mean() < 0.002, (i, outside.sum())
        assert changed[mask].any()  # the object was really removed


def test_test_views_mark_what_no_training_view_saw_the_far_dome_not_the_object(any_scene: Path):
    """The object in the middle, which every training view faces, is seen (1% unseen on the tiny scenes); what lies
    far behind it, which few of the seven training views have in frame, holds the unseen pixels (a third of a view
    here, 0-1.5% at 640x480 with 90 training views)."""
    scene = load_scene(any_scene, depth=True)
    assert sorted(scene.unseen) == scene.test
    for i in scene.test:
        unseen, depth = scene.unseen[i], scene.depths[i]
        on_target = unseen[scene.masks[i] == scene.target.id].mean()
        assert on_target < 0.05, on_target
        assert unseen[depth > np.percentile(depth, 75)].mean() > 5 * on_target


def test_hole_masks_lie_inside_the_target_mask_and_are_smaller(any_scene: Path):
    scene = load_scene(any_scene)
    target = scene.target.id
    total_hole = total_mask = 0
    for i, hole in scene.holes.items():
        mask = scene.masks[i] == target
        assert not (hole & ~mask).any()
        total_hole, total_mask = total_hole + hole.sum(), total_mask + mask.sum()
    assert 0 < total_hole < 0.9 * total_mask  # other views see part of what the object hides


def test_livingroom_target_hides_other_objects_from_several_views(living_scene: Path):
    scene = load_scene(living_scene)
    small = [o.id for o in scene.objects if not o.target]
    assert len(small) >= 3
    seen = np.array([[np.any(mask == obj) for obj in small] for mask in scene.masks])  # (views, objects)
    assert seen.mean(axis=0).min() >= 0.5  # each object is in view most of the time ...
    assert (~seen).sum() >= 3  # ... yet hidden, whole, behind the target from several views
    assert (~seen).any(axis=0).sum() >= 2  # and more than one object is


@pytest.mark.slow
def test_same_seed_gives_the_same_scene(tmp_path: Path):
    args = ["--views", "2", "--res", "32", "--samples", "1", "--seed", "7"]
    make_scene(tmp_path / "a", "tabletop", args)
    make_scene(tmp_path / "b", "tabletop", args)
    for name in ("split.json", "masks/objects.json"):
        assert (tmp_path / "a" / name).read_text() == (tmp_path / "b" / name).read_text()
    a, b = load_scene(tmp_path / "a"), load_scene(tmp_path / "b")
    assert np.array_equal(a.images[0], b.images[0]) and np.allclose(a.cameras[1].R, b.cameras[1].R)
    make_scene(tmp_path / "c", "tabletop", args[:-1] + ["8"])
    assert not np.array_equal(a.images[0], load_scene(tmp_path / "c").images[0])


@pytest.mark.slow
def test_gt_test_renders_ground_truth_only_for_test_views(tmp_path: Path):
    make_scene(tmp_path / "s", "statue", ["--views", "16", "--res", "32", "--samples", "1", "--gt", "test"])
    scene = load_scene(tmp_path / "s")
    split = json.loads((tmp_path / "s" / "split.json").read_text())
    assert split["test"] == ["0005.png", "0015.png"] and len(split["train"]) == 14
    assert sorted(scene.gt_images) == sorted(scene.holes) == scene.test


@pytest.mark.slow
def test_extra_test_views_are_test_only_with_ground_truth_and_leave_the_training_views_as_they_were(tmp_path: Path):
    """--extra-test 3 adds three test views on an orbit of their own (the set metrics' images); the training
    views and their poses are those of the same scene without them."""
    args = ["--views", "6", "--res", "32", "--samples", "1", "--gt", "test"]
    make_scene(tmp_path / "plain", "statue", args)
    make_scene(tmp_path / "extra", "statue", [*args, "--extra-test", "3"])
    plain, extra = load_scene(tmp_path / "plain"), load_scene(tmp_path / "extra")
    names = [c.name for c in extra.cameras]
    assert [names[i] for i in extra.test] == ["0005.png", "0006.png", "0007.png", "0008.png"]
    assert [names[i] for i in extra.train] == [plain.cameras[i].name for i in plain.train]
    assert all(np.allclose(extra.cameras[i].R, plain.cameras[i].R) for i in plain.train)
    assert sorted(extra.gt_images) == extra.test and not np.allclose(extra.cameras[6].R, extra.cameras[5].R)


@pytest.mark.parametrize("problem", ["existing", "engine"])
def test_make_scene_refuses_bad_runs_with_one_line(tmp_path: Path, problem: str):
    out = tmp_path / "scene"
    env = {}
    if problem == "existing":
        out.mkdir()
        (out / "keep.txt").write_text("mine")
    else:
        env = {"SPLATFILL_ENGINE_PYTHON": str(tmp_path / "no-python")}
    proc = make_scene(out, "tabletop", ["--views", "2", "--res", "32", "--samples", "1"], env=env, check=False)
    assert proc.returncode != 0
    error = [ln for ln in proc.stderr.splitlines() if ln.startswith("error:")]
    assert len(error) == 1 and ("already exists" in error[0] or "no-python" in error[0])
    if problem == "existing":
        assert (out / "keep.txt").read_text() == "mine"
    else:
        assert not out.exists() and not list(tmp_path.glob(".scene*"))  # no staging left behind


@pytest.mark.slow
def test_hemisphere_orbit_spirals_upwards(tmp_path: Path):
    args = ["--views", "6", "--res", "32", "--samples", "1", "--points", "500", "--gt", "test"]
    make_scene(tmp_path / "hemi", "statue", args + ["--orbit", "hemisphere"])
    heights = [c.center[2] for c in load_scene(tmp_path / "hemi").cameras]
    assert all(b > a - 0.05 for a, b in zip(heights, heights[1:], strict=False)) and heights[-1] > heights[0] + 0.3
