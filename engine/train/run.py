"""`python -m engine train`: a training run in its own folder, resumable and cancellable.

Run folder (engine.formats.layout.RunLayout): config.json, the resolved TrainConfig; checkpoints/, the last
`keep_checkpoints` step_XXXXXXX.pt; at the end point_cloud.ply (standard 3DGS layout + obj_dc_*),
classifier.npz (weight (C, 16), bias (C,)), objects.json (so ids have names) and metrics.json (test
PSNR/SSIM, identity mIoU, Gaussians, wall time).
The scene folder is only read. SIGINT/SIGTERM write a checkpoint and end the run with status 130;
`--resume` continues from the newest checkpoint with the saved config.
"""

from __future__ import annotations

import dataclasses
import json
import signal
import time
from pathlib import Path

import torch

from engine.base.device import pick_device
from engine.base.errors import Cancelled, InputError
from engine.base.progress import Progress, emit
from engine.base.versions import gpu_name, versions
from engine.capture.scene import load_scene
from engine.formats.layout import RunLayout
from engine.io.ply_io import save_classifier, save_ply
from engine.metrics.evaluate import evaluate_views
from engine.train.background_floaters import background_floaters
from engine.train.camera_clearance import EMPTY_LOGIT, SIGMAS, centres_of, holders_of
from engine.train.config import TrainConfig
from engine.train.trainer import Trainer


def _write_json(path: Path, data: dict) -> None:
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(data, indent=1))
    tmp.replace(path)


def save_checkpoint(run: Path, trainer: Trainer, keep: int) -> Path:
    folder = RunLayout(run).checkpoints
    folder.mkdir(exist_ok=True)
    path = folder / f"step_{trainer.step_index:07d}.pt"
    tmp = path.with_suffix(".pt.tmp")
    torch.save(trainer.state_dict(), tmp)
    tmp.replace(path)
    for old in sorted(folder.glob("step_*.pt"))[:-keep]:
        old.unlink()
    return path


def latest_checkpoint(run: Path) -> Path | None:
    found = sorted(RunLayout(run).checkpoints.glob("step_*.pt"))
    return found[-1] if found else None


def prepare_run(config: TrainConfig, resume: bool) -> TrainConfig:
    """Create the run folder (or check the one being resumed) and return the config to use."""
    run = Path(config.out)
    layout = RunLayout(run)
    if resume:
        if not layout.config_json.is_file():
            raise InputError(f"cannot resume {run}: it has no config.json; start a new run without --resume")
        return TrainConfig.from_saved(json.loads(layout.config_json.read_text()))
    if run.exists() and any(run.iterdir()):
        raise InputError(f"run folder {run} already exists: pass --resume to continue it, or choose a new --out")
    # absolute: later stages start from other folders (Blender, the benchmark) and read the scene from here
    config = dataclasses.replace(config.resolved(), scene=str(Path(config.scene).resolve()), out=str(run.resolve()))
    run.mkdir(parents=True, exist_ok=True)
    _write_json(layout.config_json, dataclasses.asdict(config))
    return config


def train(config: TrainConfig, resume: bool = False, plugins: dict | None = None,
          resume_hint: str = "--resume") -> dict:
    """Train a new run, or continue one from its newest checkpoint; returns its metrics. `plugins` are the
    Trainer's completion plug-ins (start, fixed, objective, views, classifier); a resumed run needs the same ones.
    `resume_hint` says how to continue after a cancel (a completion's run continues through `complete`)."""
    config = prepare_run(config, resume)
    run = Path(config.out)
    try:
        scene = load_scene(config.scene, config.resolution)
        if not scene.train:
            raise InputError(f"{config.scene} has no training views: check split.json")
    except InputError:
        if not resume:  # a run that never started leaves nothing that refuses the same command once fixed
            RunLayout(run).config_json.unlink(missing_ok=True)
        raise
    device = pick_device(config.device)
    trainer = Trainer(config, scene, device, **(plugins or {}))
    source = latest_checkpoint(run) if resume else None
    if source is not None:
        trainer.load_state_dict(torch.load(source, map_location="cpu", weights_only=False))
        emit("resumed", step=trainer.step_index, checkpoint=str(source))
    stop = {"signal": None}
    handlers = {s: signal.signal(s, lambda n, _f: stop.update(signal=n)) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        _loop(trainer, run, stop, resume_hint)
    finally:
        for s, h in handlers.items():
            signal.signal(s, h)
    return _finish(trainer, scene, run)


def _loop(trainer: Trainer, run: Path, stop: dict, resume_hint: str) -> None:
    config = trainer.config
    progress = Progress("train", config.steps)
    start = time.perf_counter() - trainer.seconds
    while trainer.step_index < config.steps:
        result = trainer.step()
        step = trainer.step_index
        trainer.seconds = time.perf_counter() - start  # wall clock of the loop, checkpoints included
        if step % config.log_every == 0 or step == config.steps:
            progress.update(step, loss=round(float(result.loss), 5), psnr=round(result.psnr, 2),
                            gaussians=trainer.count)
        if step % config.checkpoint_every == 0 and step < config.steps:
            save_checkpoint(run, trainer, config.keep_checkpoints)
        if stop["signal"] is not None:
            path = save_checkpoint(run, trainer, config.keep_checkpoints)
            progress.close()
            emit("cancelled", step=step, checkpoint=str(path))
            raise Cancelled(f"stopped at step {step}; checkpoint {path}; continue with {resume_hint}")
    _synchronize(trainer.device)
    trainer.seconds = time.perf_counter() - start
    progress.close()


def _synchronize(device: torch.device) -> None:
    if device.type == "cuda":
        torch.cuda.synchronize(device)


def _test_view_holders(trainer: Trainer, scene) -> dict[str, int]:
    """Per test view, the live Gaussians that hold its camera at the run's clearance depth (its default where the
    clearance is off; engine.train.camera_clearance.holders_of)."""
    views = [scene.cameras[i] for i in scene.test]
    counts = holders_of(trainer.gaussians, centres_of(views), sigmas=trainer.config.camera_clearance or SIGMAS)
    return dict(zip((camera.name for camera in views), counts, strict=True))


def _empty_background_floaters(trainer: Trainer, scene) -> int | None:
    """With --background-floaters TOLERANCE (and the black background it needs), empty the Gaussians that no
    training view can tell from the background (engine.train.background_floaters); how many, or None where it did
    not run."""
    tolerance = trainer.config.background_floaters
    if tolerance <= 0 or trainer.config.background != "black":
        return None
    floaters = background_floaters(trainer.gaussians, [scene.cameras[i] for i in scene.train], trainer.sh_degree,
                                   trainer.device, tolerance)
    trained = torch.as_tensor(floaters[trainer.fixed_count:], device=trainer.device)
    with torch.no_grad():
        opacities = trainer.params["opacities"]
        opacities.masked_fill_(trained.reshape(opacities.shape), EMPTY_LOGIT)
    return int(trained.sum())


def _finish(trainer: Trainer, scene, run: Path) -> dict:
    floaters = _empty_background_floaters(trainer, scene)
    save_checkpoint(run, trainer, trainer.config.keep_checkpoints)
    save_ply(RunLayout(run).point_cloud, trainer.gaussians)
    save_classifier(RunLayout(run).classifier, trainer.classifier)
    _write_json(RunLayout(run).objects_json, {"objects": [dataclasses.asdict(o) for o in scene.objects]})
    start = time.perf_counter()
    metrics = evaluate_views(scene, scene.test, trainer.gaussians, trainer.classifier, trainer.sh_degree,
                             trainer.device)
    metrics.update(gaussians=trainer.count, trained_gaussians=len(trainer.params["means"]), steps=trainer.step_index,
                   train_seconds=round(trainer.seconds, 2), eval_seconds=round(time.perf_counter() - start, 2),
                   device=str(trainer.device), gpu=gpu_name(trainer.device), versions=versions(),
                   peak_gpu_mb=(round(torch.cuda.max_memory_allocated() / 2**20, 1)
                                if trainer.device.type == "cuda" else None))
    metrics["camera_holders"] = int(trainer.camera_holders)  # Gaussians emptied for holding a training camera
    metrics["test_view_holders"] = _test_view_holders(trainer, scene)
    metrics["background_floaters"] = floaters  # emptied at the end (None: --background-floaters 0)
    if trainer.colours is not None:  # how far the photos' exposures strayed (the scene renders without them)
        metrics["view_colours"] = trainer.colours.report()
    _write_json(RunLayout(run).metrics_json, metrics)
    emit("done", run=str(run), **{k: v for k, v in metrics.items() if isinstance(v, (int, float, str))})
    return metrics
