"""Commands over a run folder whose line for the user needs more than their stage's report: training, segments,
completion, and scoring a finished run."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from engine.base.progress import emit
from engine.train.config import TrainConfig


@dataclass
class TrainCommandConfig(TrainConfig):
    resume: bool = False  # continue the run in --out from its newest checkpoint


def train(config: TrainCommandConfig) -> str:
    from engine.train.run import train

    settings = TrainConfig(**{k: v for k, v in vars(config).items() if k != "resume"})
    metrics = train(settings, resume=config.resume)
    miou = "n/a (no masks)" if metrics["identity_miou"] is None else f"{metrics['identity_miou']:.3f}"
    return (f"test PSNR {metrics['psnr']:.2f} dB, SSIM {metrics['ssim']:.4f}, identity mIoU {miou}, "
            f"{metrics['gaussians']} Gaussians, {metrics['train_seconds']:.0f} s")


def segment(config) -> str:
    from engine.formats.layout import RunLayout
    from engine.segment.run import run_segment
    from engine.train.trained_run import load_run

    out = Path(config.out) if config.out else RunLayout(config.run).segments.root
    report = run_segment(load_run(config.run), config)  # refuses to replace objects found before unless --replace
    said = (f"{report['objects']} objects in {out}: see {out / 'sheet.png'}, then `remove --run {config.run} "
            "--object NAME`")
    if "subject_share" not in report:
        return said
    share = f"{report['subject_share']:.1%} of the scene's Gaussians"
    if report.get("subject") == "votes":
        return f"{said}; object_1, the subject the photos are about: {share}"
    return (f"{said}; no salient subject was found, so object_1 is only the largest object ({share}): if it is not "
            f"the one, pick it with `segment --run {config.run} --point U V --view IMAGE --replace`")


def complete(config) -> str:
    from engine.complete.run import run_complete

    report = run_complete(config)
    if report["method"] is None:
        return f"{report['verdict']}: the scene is {report['scene']}; {report['hint']}"
    if report.get("nothing_to_train"):
        return f"{report['method']}: nothing trained, {report['nothing_to_train']}; pictures in {report['out']}"
    scores, removed = report["scores"], report["removed_scores"]
    if scores["m_psnr"] is None and scores.get("psnr_outside") is not None:  # a capture: no gt/
        said = (f"PSNR outside the object against the photos {scores['psnr_outside']:.2f} dB (removed, unfilled: "
                f"{removed['psnr_outside']:.2f}); no gt/, so the fill itself is judged by eye")
    else:
        said = f"m-PSNR {scores['m_psnr']} (removed, unfilled: {removed['m_psnr']}), PSNR {scores['psnr']}"
    return f"{report['method']}: {said}, {report['seconds']} s; pictures in {report['out']}"


@dataclass
class EvaluateConfig:
    run: str = ""  # the run folder to score
    removed: str = ""  # score this removal output's renders instead of the run
    out: str = ""  # JSON file to write the scores to
    device: str = "auto"  # auto | cuda | cpu


def evaluate(config: EvaluateConfig) -> str:
    from engine.base.device import pick_device
    from engine.complete.scoring import score_removed, score_run
    from engine.formats.layout import RemovedLayout
    from engine.metrics.scores import ScoreConfig, Scorer
    from engine.train.trained_run import load_run_scene

    scorer = Scorer(ScoreConfig(device=str(pick_device(config.device))))
    if config.removed:
        scores = score_removed(load_run_scene(config.run), RemovedLayout(config.removed), scorer)
    else:
        scores = score_run(Path(config.run), scorer)
    report = {"scores": scores.values, "unavailable": scores.unavailable}
    if config.out:
        Path(config.out).write_text(json.dumps(report, indent=1))
    emit("done", stage="evaluate", **report)
    return ", ".join(f"{k} {v:.4g}" for k, v in scores.values.items() if v is not None)
