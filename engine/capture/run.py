"""`python -m engine capture`: photos or a video in, a COLMAP folder out (images/ and sparse/0/), which every
later stage takes as a scene.

pycolmap's own SfM, with the defaults COLMAP and capture apps use: SIFT features, one SIMPLE_RADIAL camera,
exhaustive matching for a photo set and sequential matching for a video's frames (neighbours in time overlap;
exhaustive over hundreds of frames is quadratic; a vocabulary tree the user gives for large sets), the mapper
that places the most photos with a reason for each one left out (engine.capture.mapping), and the images
undistorted to PINHOLE as 3DGS's convert.py does. engine.capture.photos makes the images upright and small enough
first.

Resumable: OUT/.sfm/ holds the feature database and which phases finished; running the same command on the
same OUT continues after the last finished phase (photos already written are kept). capture.json, written
last, marks a finished capture. pycolmap's C++ cannot see Python's signals, so each phase runs in a worker
thread and Ctrl-C or SIGTERM cancels it through pycolmap's cancellation token.
"""

from __future__ import annotations

import json
import shutil
import signal
import threading
import time
import zlib  # noqa: F401,I001  -- before pycolmap, see engine.io.colmap_model
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import cv2  # noqa: F401

from engine.base.errors import Cancelled, InputError
from engine.base.progress import emit, say
from engine.capture.mapping import MAPPERS, map_photos, unplaced_reasons
from engine.capture.photos import JPEG_QUALITY, photo_files, prepare_photos, prepare_video
from engine.formats.layout import CaptureLayout


@dataclass
class CaptureConfig:
    images: str = ""  # a folder of photos (JPEG, PNG, ...; EXIF orientation honoured)
    video: str = ""  # or a video file (MP4, MOV, ...): its sharpest frames become the views
    out: str = ""  # a new folder: images/ and sparse/0/, the scene the later stages take
    max_size: int = 1600  # longer image side in px after downscaling (area averaging); 0 keeps the size
    frames: int = 150  # video: views taken, the sharpest frame of each equal stretch
    matching: str = "auto"  # auto (exhaustive for photos, sequential for video) | exhaustive | sequential | vocab
    vocab_tree: str = ""  # --matching vocab: COLMAP's vocabulary tree file (for sets past about 150 photos)
    mapper: str = "best"  # best (incremental; relaxed and global where it leaves photos out) | incremental | global
    min_registered: float = 0.5  # refuse when SfM registers fewer than this share of the images
    threads: int = -1  # CPU threads for SfM (-1: all)
    seed: int = 0  # the matches' and mappers' sampling seed (one thread: the same scene each run; COLMAP's -1
    # draws one a run)


def run_capture(config: CaptureConfig) -> dict:
    """Write config.out from the photos or video; returns the report (also OUT/capture.json)."""
    layout = CaptureLayout(config.out)
    out, work = layout.root, layout.work
    _check_out(layout, config)
    start = time.perf_counter()
    clock: dict[str, float] = {}
    work.mkdir(parents=True, exist_ok=True)
    layout.config_json.write_text(json.dumps(asdict(config), indent=1))
    photos = work / "input"  # upright and fitted; the undistorted images/ are made from them at the end
    names = (prepare_video(Path(config.video), photos, config.frames, config.max_size) if config.video
             else prepare_photos(photo_files(Path(config.images)), photos, config.max_size))
    clock["images"] = time.perf_counter() - start
    done = _phases_done(work)
    for phase, action in (("features", lambda token: _features(photos, names, work, config, token)),
                          ("matches", lambda token: _matches(work, config, token))):
        if phase not in done:
            began = time.perf_counter()
            _cancellable(action, lambda phase=phase: emit("phase", stage="capture", phase=phase, images=len(names)))
            clock[phase] = time.perf_counter() - began
            _mark_done(work, phase)
    began = time.perf_counter()
    mapped = _cancellable(lambda token: _mapping(photos, work, config, token, len(names)))
    clock["mapping"] = time.perf_counter() - began
    model = mapped.model
    registered = model.num_reg_images()
    left_out = unplaced_reasons(mapped, work / "database.db", photos, names)
    for name, reason in left_out.items():
        say(f"not placed: {name}: {reason}")
    report = {"images": len(names), "registered": registered, "points": model.num_points3D(),
              "mapper": mapped.mapper, "placed_by_mapper": mapped.tried, "not_placed": left_out,
              "mean_reprojection_error_px": round(model.compute_mean_reprojection_error(), 3),
              "camera": f"{model.cameras[next(iter(model.cameras))].model.name}, undistorted to PINHOLE",
              "seconds": round(time.perf_counter() - start, 1), "phases": {k: round(v, 1) for k, v in clock.items()}}
    if registered < max(3, config.min_registered * len(names)):
        (work / "report.json").write_text(json.dumps(report, indent=1))
        raise InputError(f"SfM registered {registered} of {len(names)} images of {config.images or config.video}: "
                         "too few to build a scene; take more photos that overlap (each part seen from 3+ places)")
    began = time.perf_counter()
    _cancellable(lambda token: _undistort(model, photos, work, layout, token))
    clock["undistort"] = time.perf_counter() - began
    report["seconds"] = round(time.perf_counter() - start, 1)
    report["phases"] = {k: round(v, 1) for k, v in clock.items()}
    partial = out / f".{layout.report.name}.part"
    partial.write_text(json.dumps(report, indent=1))
    partial.replace(layout.report)
    shutil.rmtree(work)
    emit("done", stage="capture", out=str(out), **{k: report[k] for k in ("images", "registered", "seconds")})
    return report


def _check_out(layout: CaptureLayout, config: CaptureConfig) -> None:
    if bool(config.images) == bool(config.video):
        raise InputError("name the photos with --images DIR or a video with --video FILE (one of the two)")
    if not config.out:
        raise InputError("name a new folder for the capture with --out")
    if config.matching not in ("auto", "exhaustive", "sequential", "vocab"):
        raise InputError(f"--matching {config.matching}: choose auto, exhaustive, sequential or vocab")
    if config.matching == "vocab" and not Path(config.vocab_tree).is_file():
        raise InputError(f"--matching vocab needs COLMAP's vocabulary tree file: --vocab-tree PATH "
                         f"({config.vocab_tree or 'none given'} is not a file; COLMAP's site lists them)")
    if config.mapper not in MAPPERS:
        raise InputError(f"--mapper {config.mapper}: choose one of {', '.join(MAPPERS)}")
    out = layout.root
    if layout.report.is_file():
        raise InputError(f"{out} is a finished capture ({layout.report.name}): train on it, or name a new --out")
    if out.is_dir() and any(out.iterdir()):
        if not layout.config_json.is_file():
            raise InputError(f"output {out} already exists and is not empty: choose a new folder for the capture")
        said = json.loads(layout.config_json.read_text())
        if (said.get("images"), said.get("video")) != (config.images, config.video):
            raise InputError(f"{out} holds a stopped capture of other images: name a new --out")
        say(f"continuing the stopped capture in {out}")


def _phases_done(work: Path) -> set[str]:
    path = work / "done.json"
    return set(json.loads(path.read_text())) if path.is_file() else set()


def _mark_done(work: Path, phase: str) -> None:
    (work / "done.json").write_text(json.dumps(sorted(_phases_done(work) | {phase})))


def _cancellable(action: Callable, started: Callable[[], None] = lambda: None):
    """Run `action(token)` in a worker thread; Ctrl-C or SIGTERM cancels it through pycolmap's token and raises
    Cancelled once it has stopped (the phases finished so far are kept). `started` announces the phase once the
    signal handlers are in place, so a stop sent on seeing it is always caught."""
    import pycolmap

    pycolmap.logging.minloglevel = 1  # warnings and errors: the progress lines say the rest
    token, result, stopped = pycolmap.CancellationToken(), {}, {}

    def work() -> None:
        try:
            result["value"] = action(token)
        except BaseException as exc:  # handed to the main thread
            result["error"] = exc

    def stop(number: int, _frame) -> None:
        stopped["signal"] = number
        token.cancel()

    handlers = {s: signal.signal(s, stop) for s in (signal.SIGINT, signal.SIGTERM)}
    thread = threading.Thread(target=work, daemon=True)
    try:
        started()
        thread.start()
        while thread.is_alive():
            thread.join(0.2)
    finally:
        for s, h in handlers.items():
            signal.signal(s, h)
    if stopped:
        raise Cancelled("capture stopped; run the same command again to continue")
    if "error" in result:
        raise result["error"]
    return result["value"]


def _features(images: Path, names: list[str], work: Path, config: CaptureConfig, token) -> None:
    import pycolmap

    reader = pycolmap.ImageReaderOptions()
    reader.camera_model = "SIMPLE_RADIAL"
    extraction = pycolmap.FeatureExtractionOptions()
    extraction.num_threads = config.threads
    pycolmap.extract_features(work / "database.db", images, image_names=names,
                              camera_mode=pycolmap.CameraMode.SINGLE, reader_options=reader,
                              extraction_options=extraction, device=pycolmap.Device.cpu, cancellation_token=token)


def _matches(work: Path, config: CaptureConfig, token) -> None:
    import pycolmap

    sequential = config.matching == "sequential" or (config.matching == "auto" and bool(config.video))
    options = pycolmap.FeatureMatchingOptions()
    options.num_threads = config.threads
    verification = pycolmap.TwoViewGeometryOptions()  # RANSAC seeded: the same photos give the same matches
    verification.ransac.random_seed = config.seed
    common = dict(matching_options=options, verification_options=verification, device=pycolmap.Device.cpu,
                  cancellation_token=token)
    if config.matching == "vocab":
        pairing = pycolmap.VocabTreePairingOptions()
        pairing.vocab_tree_path = config.vocab_tree
        pycolmap.match_vocabtree(work / "database.db", pairing_options=pairing, **common)
    elif sequential:
        pycolmap.match_sequential(work / "database.db", **common)
    else:
        pycolmap.match_exhaustive(work / "database.db", **common)


def _mapping(images: Path, work: Path, config: CaptureConfig, token, total: int):
    """The reconstruction placing the most photos (engine.capture.mapping; progress per registered image)."""
    from engine.base.progress import Progress

    progress, count = Progress("mapping", total), {"n": 0}

    def registered() -> None:
        count["n"] += 1
        progress.update(min(count["n"], total))

    shutil.rmtree(work / "sparse", ignore_errors=True)
    mapped = map_photos(work / "database.db", images, work / "sparse", config.mapper, config.threads, token,
                        registered, seed=config.seed)
    progress.close()
    if token.is_cancelled:
        return None
    if mapped is None or mapped.model is None:
        raise InputError(f"SfM registered none of the {total} images in {images}: the photos share too few "
                         "features; take overlapping photos of a textured scene")
    return mapped


def _undistort(model, photos: Path, work: Path, layout: CaptureLayout, token) -> None:
    """The registered photos undistorted to PINHOLE cameras (COLMAP's image_undistorter, as 3DGS's convert.py
    runs it) into OUT/images and OUT/sparse/0: every reader, ours and other 3DGS code, takes them as they are."""
    import pycolmap

    for folder in ("model", "undistorted"):
        shutil.rmtree(work / folder, ignore_errors=True)
    (work / "model").mkdir()
    model.write_binary(str(work / "model"))
    pycolmap.undistort_images(work / "undistorted", work / "model", photos, jpeg_quality=JPEG_QUALITY,
                              num_threads=-1, cancellation_token=token)
    if token.is_cancelled:
        return
    for target in (layout.images, layout.sparse):
        shutil.rmtree(target, ignore_errors=True)
    (work / "undistorted" / "images").rename(layout.images)
    layout.sparse.mkdir()
    (work / "undistorted" / "sparse").rename(layout.sparse / "0")
