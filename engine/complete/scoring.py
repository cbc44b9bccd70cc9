"""Scores of a completed run, or of the removed-but-unfilled scene, on the test views: against gt/ inside the
scene's holes/ where a generated scene has them (engine.metrics.scores does the measuring), else the
reference-free numbers a user's capture allows.

A capture has no picture of the scene without the object, so nothing can say how right the fill is. What
can be measured is whether the rest of the scene survived: PSNR against the input photos outside the
object's region and its effects (the removal's masks/ and effects/, grown by `OUTSIDE_MARGIN` px), where
the object never was (`psnr_outside`). Every other column is None with the reason."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from engine.base.device import pick_device
from engine.capture.scene import Scene
from engine.formats.layout import RemovedLayout
from engine.io.image_io import read_png, write_png
from engine.io.masks import dilate, optional_mask
from engine.metrics.image_metrics import psnr_from_mse
from engine.metrics.scores import Scorer, Scores, pixel_scores
from engine.render.render_views import render_pictures
from engine.train.trained_run import load_run, load_splats

ORACLE_BLUR = 4.0  # px: sigma of the blurred-truth oracle
CHANGED_LEVELS = 8  # of 255: a pixel a completion changed (kept_changes)
NEAR_HOLE_PX = 16  # kept_changes: changes this close to the hole count as spilled from it
OUTSIDE_MARGIN = 8  # px around the object's region and effects left out of psnr_outside (soft edges, blur)
NO_GT = "no gt/: a capture has no picture without the object (psnr_outside is the reference-free score)"


def has_truth(scene: Scene) -> bool:
    """Whether every test view has gt/ and holes/ (a generated scene): the full scores apply."""
    return bool(scene.test) and all(i in scene.gt_images and i in scene.holes for i in scene.test)


def score_run(run_dir: Path, scorer: Scorer, renders: Path | None = None, scene: Scene | None = None,
              removed: RemovedLayout | None = None) -> Scores:
    """Scores of a trained run's test renders (against gt/ and holes/, or reference-free against the input
    photos outside `removed`'s regions); the renders are saved under `renders` when given (the benchmark's
    side-by-side pictures read them). `scene`: the test views' cameras, gt/ and holes/ when the caller holds
    them already (a completion's training scene copies the original's), so the run's scene is not read from
    disk a third time in one cell."""
    if scene is None:
        run = load_run(run_dir)
        scene, gaussians, sh_degree = run.scene, run.gaussians, run.sh_degree
    else:
        gaussians, sh_degree = load_splats(run_dir)
    views = scene.test
    pictures = [p.rgb for p in render_pictures(gaussians, [scene.cameras[i] for i in views], sh_degree,
                                               pick_device(scorer.config.device), depth=False)]
    if renders is not None:
        for i, rgb in zip(views, pictures, strict=True):
            write_png(renders / scene.cameras[i].name, rgb)
    return _scores(scene, views, pictures, scorer, removed)


def score_removed(scene: Scene, removed: RemovedLayout, scorer: Scorer) -> Scores:
    """The same scores for the removed-but-unfilled scene's renders (the floor every method must beat)."""
    views = scene.test
    renders = [read_png(removed.images / scene.cameras[i].name, size=scene.cameras[i].size) for i in views]
    return _scores(scene, views, renders, scorer, removed)


def score_oracles(scene: Scene) -> dict[str, dict] | None:
    """Pixel scores of two fills no method can beat without knowing the texture, beside which a table shows how
    much any fill could still gain: the true hole filled with the truth's mean colour over it (`flat`), and the
    truth blurred by ORACLE_BLUR px inside it (`blur`, the texture's coarse shape). None without gt/."""
    if not has_truth(scene):
        return None
    truths = [scene.gt_images[i] for i in scene.test]
    holes = [scene.holes[i] for i in scene.test]
    flat, blur = [], []
    for truth, hole in zip(truths, holes, strict=True):
        mean = truth[hole].mean(axis=0).round() if hole.any() else 0
        flat.append(np.where(hole[..., None], mean, truth).astype(np.uint8))
        blur.append(np.where(hole[..., None], cv2.GaussianBlur(truth, (0, 0), ORACLE_BLUR), truth))
    return {"flat": pixel_scores(flat, truths, holes), "blur": pixel_scores(blur, truths, holes)}


def _scores(scene: Scene, views: list[int], pictures: list[np.ndarray], scorer: Scorer,
            removed: RemovedLayout | None) -> Scores:
    if has_truth(scene):
        return scorer.score(pictures, [scene.gt_images[i] for i in views], [scene.holes[i] for i in views])
    outside = [None if removed is None else ~_object_pixels(removed, scene, i) for i in views]
    return reference_free(pictures, [scene.images[i] for i in views], outside)


def _object_pixels(removed: RemovedLayout, scene: Scene, i: int) -> np.ndarray:
    """The removed object's region and its effects in view i, grown by OUTSIDE_MARGIN."""
    camera = scene.cameras[i]
    region = optional_mask(removed.masks / camera.name, camera.size)
    return dilate(region | optional_mask(removed.effects.mask(camera.name), camera.size), OUTSIDE_MARGIN)


def reference_free(renders: list[np.ndarray], photos: list[np.ndarray], outside: list[np.ndarray | None]) -> Scores:
    """PSNR of each render against its input photo over the pixels `outside` the object (all pixels where
    None), averaged over the views; the ground-truth columns None with the reason."""
    values: list[float] = []
    for render, photo, keep in zip(renders, photos, outside, strict=True):
        keep = np.ones(render.shape[:2], bool) if keep is None else keep
        if keep.any():
            diff = (render.astype(np.float64) - photo) / 255.0
            values.append(psnr_from_mse(float((diff[keep] ** 2).mean())))
    keys = ("psnr", "ssim", "m_psnr", "m_ssim", "lpips", "m_lpips", "st_lpips", "m_st_lpips", "fid", "kid",
            "m_fid", "m_kid")
    result = {k: None for k in keys} | {"psnr_outside": float(np.mean(values)) if values else None}
    return Scores(values=result, unavailable={k: NO_GT for k in keys})


def psnr_kept(scene: Scene, renders: Path, removed: RemovedLayout, holes: dict[int, np.ndarray]
              ) -> tuple[float | None, dict[str, dict]]:
    """PSNR of the completed test renders (`renders`) against the removed scene's, outside each view's hole as
    the inpainting grew it (`holes`), averaged over the test views: how well a completion left alone what it
    had no reason to touch (engine.complete.hole_region). None without test views. With it, per test view,
    where the changes lie (kept_changes)."""
    cameras = [scene.cameras[i] for i in scene.test]
    after = [read_png(renders / c.name, size=c.size) for c in cameras]
    before = [read_png(removed.images / c.name, size=c.size) for c in cameras]
    outside = [~holes[i] for i in scene.test]
    views = {c.name: kept_changes(a, b, keep) for c, a, b, keep in zip(cameras, after, before, outside, strict=True)}
    return reference_free(after, before, outside).values["psnr_outside"], views


def kept_changes(after: np.ndarray, before: np.ndarray, outside: np.ndarray) -> dict:
    """Outside the hole of one view: the PSNR of `after` against `before`, the share of its pixels changed by more
    than CHANGED_LEVELS in some channel, and the share of those within NEAR_HOLE_PX of the hole. Why: a completion
    that blurs what it should keep changes many pixels a little, everywhere; one whose Gaussians spill past the
    hole changes few, by much, beside it; the mean PSNR alone (30.2 dB on the statue capture at dd16d65) tells
    neither."""
    diff = np.abs(after.astype(np.int16) - before.astype(np.int16)).max(-1)
    changed = (diff > CHANGED_LEVELS) & outside
    near = dilate(~outside, NEAR_HOLE_PX)
    count = max(int(outside.sum()), 1)
    value = reference_free([after], [before], [outside]).values["psnr_outside"]
    return {"psnr": round(value, 2) if value is not None and np.isfinite(value) else None,  # nothing outside or changed
            "changed_share": round(int(changed.sum()) / count, 5),
            "changed_near_hole": round(int((changed & near).sum()) / max(int(changed.sum()), 1), 3)}
