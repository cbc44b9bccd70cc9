"""Stage 5: complete the scene from the inpainted views with one completion method, and score the result.

Every method runs through this one loop: its training scene is written as a folder of its own,
RUN/complete/<Name>/scene (engine.complete.training_scene, atomically); RUN/complete/<Name>/run is an
ordinary training run with the method's settings and Trainer plug-ins; renders/ holds its test views; and
scores.json, written last and atomically, holds engine.metrics.scores on the test views beside the same
metrics for the removed-but-unfilled scene (reference-free on a capture without gt/, engine.complete.scoring);
turntable/turntable.mp4 shows the scene before and after. What differs between methods lives in their plug-in
files (engine.complete.methods, found through engine.complete.registry). A stopped completion continues when the
same command runs again (or with --resume): from its last checkpoint, from its written training scene, or from
the start where it stopped before either existed.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path

import torch

from engine.base.config_cli import add_option
from engine.base.defaults import DEFAULT_INPAINTER, DEFAULT_METHOD, LEFT, WHY
from engine.base.device import pick_device
from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir, check_new_output
from engine.base.progress import emit
from engine.base.versions import gpu_name, versions
from engine.complete.registry import CompletionMethod, all_options, fill_hint, get, methods, resolve_options
from engine.complete.scoring import psnr_kept, score_oracles, score_removed, score_run
from engine.complete.training_scene import write_training_scene
from engine.formats.layout import CompleteLayout, HolesLayout, InpaintedLayout, RemovedLayout, SceneLayout
from engine.inpaint.run import inpainted_dilation, inpainted_holes
from engine.io.masks import read_masks
from engine.metrics.scores import ScoreConfig, Scorer
from engine.train.run import train
from engine.train.trained_run import TrainedRun, load_run


@dataclass
class CompleteConfig:
    run: str = ""  # the training run to complete
    method: str = DEFAULT_METHOD  # init | reference | ft | direct (`engine plugins`); "": leave the hole (LEFT)
    inpainter: str = DEFAULT_INPAINTER  # whose inpainted views to train on
    inpainted: str = ""  # default RUN/inpainted/<inpainter> (direct: RUN/inpainted/direct-<inpainter>)
    removed: str = ""  # default RUN/removed (its removal.json names the object; its renders are the baseline)
    holes: str = ""  # ft and --warm: default the holes the inpainting filled, else RUN/holes
    out: str = ""  # default RUN/complete/<Name>
    steps: int = 0  # 0: the training run's own (init, direct) or a tenth of it (ft)
    seed: int = 0  # random seed of the completion's training
    device: str = "auto"  # auto | cuda | cpu
    lpips_backbone: str = ""  # alexnet-owt-7be5be79.pth for LPIPS (default LPIPS_BACKBONE or torch's hub cache)
    lpips_heads: str = ""  # lpips' weights/v0.1/alex.pth (default: from the installed lpips package)
    fid_weights: str = ""  # FID Inception weights (default FID_INCEPTION or the set-up's .weights/)
    resume: bool = False  # continue the stopped completion in --out (running the same command again does too)
    turntable: bool = True  # write turntable/turntable.mp4, the scene before and after, around the object
    options: dict = field(default_factory=dict)  # the method's own options (engine.complete.registry)


@dataclass
class CompletionJob:
    """What a method's hooks see: the settings, the original run and the folders it reads and writes."""

    config: CompleteConfig
    method: CompletionMethod
    options: dict
    original: TrainedRun
    removed: RemovedLayout
    inpainted: InpaintedLayout
    holes: HolesLayout
    out: CompleteLayout
    device: torch.device
    notes: dict = field(default_factory=dict)  # what a hook tells the report (nothing_to_train: why)

    def short_steps(self) -> int:
        """--steps, else a tenth of the base run's (at least 100), counted in views as a completion's steps are
        (one a step: a base run of 7,500 steps of 4 views gives 3,000): the runs that start from the base run's
        scene instead of from scratch (FT, and --warm's new scenes)."""
        return self.config.steps or max(self.original.config.one_view_a_step().steps // 10, 100)


def add_method_arguments(parser: argparse.ArgumentParser) -> None:
    """--method and every registered method's options (the common flags come from CompleteConfig)."""
    parser.add_argument("--method", default=DEFAULT_METHOD, choices=["", *methods()],
                        help=f"(default: {DEFAULT_METHOD or 'none'}: {WHY}; {LEFT})")
    for option in all_options().values():
        add_option(parser, option.name, option.default, f"{option.help} (default: {option.default})"
                   if isinstance(option.default, bool) else option.help, choices=option.choices)


def config_from_args(args: argparse.Namespace) -> CompleteConfig:
    common = {f.name: getattr(args, f.name) for f in dataclasses.fields(CompleteConfig) if f.name != "options"}
    return CompleteConfig(**common, options={name: getattr(args, name) for name in all_options()})


def run_complete(config: CompleteConfig) -> dict:
    if not config.method:
        return leave_hole(config)
    loading = time.perf_counter()
    job = _job(config)
    out, original = job.out, job.original
    start = time.perf_counter()
    # where a cell's own time goes, seconds by phase (a benchmark matrix's time is mostly its cells)
    clock = {"load": start - loading}
    if out.scene.root.is_dir():  # a stopped run's training scene, with the report of its making
        colmap = json.loads(out.recolmap_json.read_text()) if out.recolmap_json.is_file() else None
    else:
        keep = job.method.keep_regions(job)
        target = json.loads(job.removed.report.read_text()).get("object")
        with atomic_output_dir(out.scene.root) as tmp:
            write_training_scene(original.scene, job.inpainted, target and target["id"], SceneLayout(tmp), keep)
            colmap = job.method.after_scene(job, tmp)
        if colmap is not None:
            out.recolmap_json.write_text(json.dumps(colmap, indent=1))
    clock["scene"] = time.perf_counter() - start
    base = original.config.one_view_a_step()  # a completion's steps are views: one a step
    settings = dataclasses.replace(base.with_steps(config.steps or base.steps),
                                   scene=str(out.scene.root), out=str(out.run.root), seed=config.seed,
                                   device=config.device, resolution=1,  # the scene is written at the run's size
                                   colour_correction="off")  # the fill takes the photos' colours, as the scene
    settings, plugins = job.method.setup(job, settings)
    metrics = train(settings, resume=out.run.config_json.is_file(), plugins=plugins,
                    resume_hint="the same `python -m engine complete` command (or with --resume)")
    kept = job.method.after_train(job)  # the trained part kept to the hole (grafted, or confined)
    if kept:
        metrics = {**metrics, "gaussians": kept.get("gaussians", metrics["gaussians"]), "kept_to_hole": kept}
    seconds = time.perf_counter() - start
    clock["train"] = seconds - clock["scene"]
    clock["train_loop"] = float(metrics.get("train_seconds", 0.0))
    return _score(job, metrics, seconds, colmap, clock)


def leave_hole(config: CompleteConfig) -> dict:
    """`--method ''` (LEFT; the default before 2f7158c): nothing is trained or written; the report names the removed
    scene, which is the result, and how to fill the hole."""
    run = load_run(config.run).layout
    removed = RemovedLayout(config.removed) if config.removed else run.removed
    if not removed.point_cloud.is_file():
        raise InputError(f"{removed.point_cloud} missing: run `python -m engine remove --run {run.root}` first")
    report = {"method": None, "verdict": LEFT, "scene": str(removed.point_cloud), "hint": fill_hint(config.run)}
    emit("done", stage="complete", method=None, scene=report["scene"], verdict=LEFT)
    return report


def _job(config: CompleteConfig) -> CompletionJob:
    method = get(config.method)
    options = resolve_options(method, config.options)
    original = load_run(config.run)
    run = original.layout
    removed = RemovedLayout(config.removed) if config.removed else run.removed
    inpainted = (InpaintedLayout(config.inpainted) if config.inpainted
                 else run.inpainted(config.inpainter, method.source))
    inpaint = f"inpaint --inpainter {config.inpainter}" + (" --source input" if method.source == "input" else "")
    for path, command in ((removed.root, "remove"), (inpainted.root, inpaint)):
        if not path.is_dir():
            raise InputError(f"{path} missing: run `python -m engine {command} --run {run.root}` first")
    name = method.title(config.inpainter, options)
    out = CompleteLayout(config.out) if config.out else run.complete(name)
    _prepare_restart(out, config.resume)
    job = CompletionJob(config=config, method=method, options=options, original=original, removed=removed,
                        inpainted=inpainted, holes=_holes(config, inpainted, run.holes),
                        out=out, device=pick_device(config.device))
    method.check(job)
    return job


def _holes(config: CompleteConfig, inpainted: InpaintedLayout, default: HolesLayout) -> HolesLayout:
    """--holes, else the holes the inpainting filled (its config names them), else RUN/holes."""
    named = config.holes or inpainted_holes(inpainted)
    return HolesLayout(named) if named else default


OWN_NAMES = {"scene", "run", "renders", "turntable", "recolmap.json"}  # what `complete` writes in its folder


def _prepare_restart(out: CompleteLayout, resume: bool) -> None:
    """Make `out` ready for a new or a stopped completion: a finished one (scores.json) is refused; a stopped
    one keeps its training scene (written atomically, so whole or absent) and its training run if that started
    (train resumes it from the newest checkpoint); renders, a turntable and a run that never wrote its
    config.json are redone. A folder holding anything `complete` does not write is refused, never emptied."""
    if out.scores_json.is_file():
        raise InputError(f"{out.root} is finished ({out.scores_json.name} exists): name a new --out to run it again")
    if not out.root.is_dir() or not any(out.root.iterdir()):
        if resume:
            raise InputError(f"nothing to resume in {out.root}: run the command without --resume")
        return
    foreign = [p.name for p in out.root.iterdir() if p.name not in OWN_NAMES and not p.name.startswith(".")]
    if foreign:
        check_new_output(out.root)  # not a completion's folder: refuse, naming it
    if not out.run.config_json.is_file():
        shutil.rmtree(out.run.root, ignore_errors=True)  # stopped before its first step: nothing to keep
    for partial in (out.renders, out.root / "turntable", *out.root.glob(".*.tmp-*")):
        shutil.rmtree(partial, ignore_errors=True)  # redone; an atomic write cut short
    emit("restart", stage="complete", out=str(out.root), scene=out.scene.root.is_dir(),
         training=out.run.config_json.is_file())


def _turntable(job: CompletionJob) -> Path | None:
    """The before/after turntable around the removed object (engine.pictures.turntable), or None when off."""
    if not job.config.turntable:
        return None
    from engine.pictures.turntable import TurntableConfig, make_turntable

    return make_turntable(TurntableConfig(run=str(job.original.layout.root), removed=str(job.removed.root),
                                          out=str(job.out.root / "turntable"), after=str(job.out.run.point_cloud),
                                          device=str(job.device)))


def _kept(job: CompletionJob) -> tuple[float | None, dict | None]:
    """PSNR against the removed scene outside the holes as inpainted, and per test view where the changes lie
    (engine.complete.scoring.psnr_kept); None where the run has no holes folder."""
    if not job.holes.root.is_dir():
        return None, None
    scene = job.original.scene
    grown = read_masks(job.holes.root, scene.cameras, inpainted_dilation(job.inpainted))
    return psnr_kept(scene, job.out.renders, job.removed, grown)


def _score(job: CompletionJob, metrics: dict, seconds: float, colmap: dict | None, clock: dict) -> dict:
    config, out = job.config, job.out
    start = time.perf_counter()
    scorer = Scorer(ScoreConfig(lpips_backbone=config.lpips_backbone, lpips_heads=config.lpips_heads,
                                fid_weights=config.fid_weights, device=str(job.device)))
    scores = score_run(out.run.root, scorer, renders=out.renders, scene=job.original.scene, removed=job.removed)
    scores.values["psnr_kept"], kept_views = _kept(job)
    baseline = score_removed(job.original.scene, job.removed, scorer)
    name = job.method.title(config.inpainter, job.options)
    settings = {k: v for k, v in dataclasses.asdict(config).items() if k != "options"} | job.options
    settings["steps"] = metrics.get("steps") or config.steps  # what it trained, where --steps 0 left it to the method
    clock["score"] = time.perf_counter() - start
    video = _turntable(job)
    report = {"method": name, "out": str(out.root), "config": settings, "seconds": round(seconds, 1),
              "phases": {k: round(v, 2) for k, v in clock.items()},
              "gaussians": metrics["gaussians"], "scores": scores.values, "unavailable": scores.unavailable,
              "removed_scores": baseline.values, "oracle_scores": score_oracles(job.original.scene),
              "recolmap": colmap, "kept_to_hole": metrics.get("kept_to_hole"),
              "kept_views": kept_views, **job.notes,
              "turntable": video and str(video.relative_to(out.root)), "gpu": gpu_name(job.device),
              "versions": versions()}
    partial = out.root / ".scores.json.tmp"
    partial.write_text(json.dumps(report, indent=1))
    partial.replace(out.scores_json)  # written last: a folder with scores.json is a finished cell
    emit("done", stage="complete", method=name, out=str(out.root), m_psnr=report["scores"]["m_psnr"],
         psnr_outside=report["scores"].get("psnr_outside"), psnr_kept=report["scores"]["psnr_kept"])
    return report
