"""`capture` places every photo it can and says why it left any out (engine.capture.mapping): a generated
livingroom's 40 views, where COLMAP's incremental mapper alone placed 36 and the global mapper all 40, plus a
photo of noise that matches nothing."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest

from tests.capture.test_user_path import orbit_scene

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def photos(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("mapping") / "photos"
    shutil.copytree(orbit_scene(tmp_path_factory) / "images", out)
    noise = np.random.default_rng(0).integers(0, 256, (192, 256, 3), dtype=np.uint8)
    cv2.imwrite(str(out / "zz_noise.png"), noise)
    return out


def capture(photos: Path, out: Path, mapper: str) -> dict:
    from engine.capture.run import CaptureConfig, run_capture

    return run_capture(CaptureConfig(images=str(photos), out=str(out), mapper=mapper, threads=2))


def test_every_photo_is_placed_or_given_a_reason(photos: Path, tmp_path: Path):
    report = capture(photos, tmp_path / "best", "best")
    assert report["images"] == 41 and report["registered"] == 40, report  # incremental alone: 36 (measured)
    assert set(report["not_placed"]) == {"zz_noise.png"}, report["not_placed"]
    assert report["not_placed"]["zz_noise.png"].startswith("too few matches"), report["not_placed"]
    assert report["placed_by_mapper"]["incremental"] < 40 and report["mapper"] != "incremental", report
    written = json.loads((tmp_path / "best" / "capture.json").read_text())
    assert written["not_placed"] == report["not_placed"]
    assert len(list((tmp_path / "best" / "images").iterdir())) == 40


def test_the_incremental_mapper_alone_leaves_photos_out_with_their_reasons(photos: Path, tmp_path: Path):
    report = capture(photos, tmp_path / "incremental", "incremental")
    assert report["mapper"] == "incremental" and list(report["placed_by_mapper"]) == ["incremental"]
    assert report["registered"] < 40 and len(report["not_placed"]) == 41 - report["registered"], report
    assert all(reason for reason in report["not_placed"].values())


@pytest.fixture(scope="module")
def orbit_video(photos: Path, tmp_path_factory) -> Path:
    """The orbit's 40 renders as an MP4, each view held for three frames of which the first and last are blurred
    as a shaking hand blurs them."""
    from engine.pictures.video import write_mp4

    root = tmp_path_factory.mktemp("video")
    frames = []
    for k, path in enumerate(sorted(p for p in photos.iterdir() if not p.name.startswith("zz_"))):
        image = cv2.imread(str(path))
        for j, sigma in enumerate((3.0, 0.0, 2.0)):
            out = root / "frames" / f"{3 * k + j:04d}.png"
            out.parent.mkdir(exist_ok=True)
            cv2.imwrite(str(out), cv2.GaussianBlur(image, (0, 0), sigma) if sigma else image)
            frames.append(out)
    return write_mp4(frames, root / "orbit.mp4", fps=12)


def test_a_video_of_an_orbit_registers_from_its_sharpest_frames(orbit_video: Path, tmp_path: Path):
    """`capture --video --frames 40` keeps the sharp frame of each view, and the frames register (sequential
    matching, as for any video)."""
    from engine.capture.run import CaptureConfig, run_capture

    report = run_capture(CaptureConfig(video=str(orbit_video), out=str(tmp_path / "capture"), frames=40, threads=2))
    kept = sorted(p.name for p in (tmp_path / "capture" / "images").iterdir())
    # 36 or more of 40 alone (40 with the whole capture folder's tests in one process), 33 once in a full `make test`
    # (two workers at once, session 43) and 19 in both of session 47's, one thread or two: the global mapper then
    # split the frames into models of 19 and 13. Issue 59's weak-frame guard is open
    assert report["images"] == 40 and report["registered"] >= 32, report
    assert all(int(name[6:11]) % 3 == 1 for name in kept), kept  # the middle, sharp frame of each view


def test_the_model_kept_is_extended_with_the_frames_it_left_out(orbit_video: Path, tmp_path: Path,
                                                                tmp_path_factory):
    """The global mapper placed 27 and 34 of the video's 40 frames on CI's machine (all 40 here): with six
    consecutive frames taken out of a model of the video, `extend` places them back where they truly are (COLMAP's
    own registration thresholds placed two of the six). The model is the scene's true cameras with points
    triangulated from the video's matches, not the global mapper's: that one put a frame 5.5 times the scene's size
    away in some runs here, and the test then judged the extension against a wrong model."""
    import zlib  # noqa: F401,I001  -- before pycolmap, see engine/io/colmap_model.py
    import pycolmap

    from engine.capture.mapping import extend, placed_names
    from engine.capture.photos import prepare_video
    from engine.complete.recolmap import umeyama

    frames, database = tmp_path / "frames", tmp_path / "database.db"
    names = prepare_video(orbit_video, frames, 40, 1600)
    pycolmap.extract_features(database, frames, image_names=names, camera_mode=pycolmap.CameraMode.SINGLE,
                              device=pycolmap.Device.cpu)
    verification = pycolmap.TwoViewGeometryOptions()
    verification.ransac.random_seed = 0
    pycolmap.match_sequential(database, verification_options=verification, device=pycolmap.Device.cpu)
    truth = pycolmap.Reconstruction(str(orbit_scene(tmp_path_factory) / "sparse" / "0"))
    full = true_model(truth, database, frames, tmp_path / "triangulated")
    ordered = sorted(full.reg_image_ids(), key=lambda i: full.images[i].name)
    cut = pycolmap.Reconstruction(full)
    for image_id in ordered[5:11]:
        cut.deregister_frame(cut.images[image_id].frame_id)
    extended = max(extend(cut, database, frames, tmp_path / "extended", 1, None, None).values(),
                   key=lambda model: model.num_reg_images())
    cut_names = {full.images[i].name for i in ordered[5:11]}
    back = sorted(cut_names & placed_names(extended))
    assert len(back) >= 5, sorted(cut_names - set(back))  # 6 of 6 in 48 runs of 48; COLMAP's thresholds: 2
    placed, true = centres(extended), centres(full)
    kept = [name for name in placed if name not in cut_names]
    onto = umeyama(np.array([placed[n] for n in kept]), np.array([true[n] for n in kept]))
    size = np.linalg.norm(np.array(list(true.values())) - np.mean(list(true.values()), axis=0), axis=1).mean()
    error = np.linalg.norm(onto.points(np.array([placed[n] for n in back])) - np.array([true[n] for n in back]),
                           axis=1) / size
    # 1-6% in 47 scratch runs of 48 here, 9.9% in one (the extension's bundle adjustment bent the loop's far end);
    # a frame the global mapper misplaced (above) was 5.5 times the scene's size off
    assert error.max() < 0.15, error.round(3)


def centres(model) -> dict[str, np.ndarray]:
    """Each registered photo's camera centre, by name."""
    return {model.images[i].name: model.images[i].projection_center() for i in model.reg_image_ids()}


def true_model(truth, database: Path, frames: Path, out: Path):
    """The video's frames at the scene's true poses (frame 3k+1 is view k) with one camera of the true focal
    length, and points triangulated from the database's matches: a model with no mapper's error in it."""
    import pycolmap

    db = pycolmap.Database.open(database)
    try:
        camera, images = db.read_all_cameras()[0], db.read_all_images()
        keypoints = {image.image_id: db.read_keypoints(image.image_id)[:, :2].astype(np.float64) for image in images}
    finally:
        db.close()
    poses = {truth.images[i].name: truth.images[i].cam_from_world() for i in truth.reg_image_ids()}
    lens = next(iter(truth.cameras.values())).params
    model = pycolmap.Reconstruction()
    model.add_camera_with_trivial_rig(pycolmap.Camera(
        model="SIMPLE_RADIAL", width=camera.width, height=camera.height, camera_id=camera.camera_id,
        params=[lens[0], lens[2], lens[3], 0.0]))
    for image in images:
        view = f"{(int(image.name[6:11]) - 1) // 3:04d}.png"
        model.add_image_with_trivial_frame(pycolmap.Image(name=image.name, keypoints=keypoints[image.image_id],
                                                          camera_id=camera.camera_id, image_id=image.image_id),
                                           poses[view])
    out.mkdir()
    return pycolmap.triangulate_points(model, database, frames, out)
