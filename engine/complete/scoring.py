"""Scores of a completed run, or of the removed-but-unfilled scene, on the test views against gt/ inside
the scene's holes/ (engine.metrics.scores does the measuring)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from engine.base.device import pick_device
from engine.base.errors import InputError
from engine.formats.layout import RemovedLayout
from engine.io.image_io import read_png, write_png
from engine.io.scene import Scene
from engine.metrics.scores import Scorer, Scores
from engine.render.render_views import render_pictures
from engine.train.trained_run import load_run, load_splats


def _test_sets(scene: Scene) -> tuple[list[int], list[np.ndarray], list[np.ndarray]]:
    views = [i for i in scene.test if i in scene.gt_images and i in scene.holes]
    if not views:
        raise InputError(f"{scene.root} has no test views with gt/ and holes/: scores need a generated scene")
    return views, [scene.gt_images[i] for i in views], [scene.holes[i] for i in views]


def score_run(run_dir: Path, scorer: Scorer, renders: Path | None = None, scene: Scene | None = None) -> Scores:
    """Scores of a trained run's test renders against its scene's gt/, masked by holes/; the renders are
    saved under `renders` when given (the benchmark's side-by-side pictures read them). `scene`: the test
    views' cameras, gt/ and holes/ when the caller holds them already (a completion's training scene copies
    the original's), so the run's scene is not read from disk a third time in one cell."""
    if scene is None:
        run = load_run(run_dir)
        scene, gaussians, sh_degree = run.scene, run.gaussians, run.sh_degree
    else:
        gaussians, sh_degree = load_splats(run_dir)
    views, truths, holes = _test_sets(scene)
    pictures = [p.rgb for p in render_pictures(gaussians, [scene.cameras[i] for i in views], sh_degree,
                                               pick_device(scorer.config.device), depth=False)]
    if renders is not None:
        for i, rgb in zip(views, pictures, strict=True):
            write_png(renders / scene.cameras[i].name, rgb)
    return scorer.score(pictures, truths, holes)


def score_removed(scene: Scene, removed: RemovedLayout, scorer: Scorer) -> Scores:
    """The same scores for the removed-but-unfilled scene's renders (the floor every method must beat)."""
    views, truths, holes = _test_sets(scene)
    renders = [read_png(removed.images / scene.cameras[i].name, size=scene.cameras[i].size) for i in views]
    return scorer.score(renders, truths, holes)
