"""The warm start of the methods that train a new scene (`--warm`, engine.complete.retrain).

Why a start from the removed scene is honest for Init and Direct: outside the object's region their training
images are the input images the base run already fitted, so its Gaussians there are what a new run would
relearn; inside the region they are the removed scene's (its hole, its see-through), which the inpainted images
then retrain like everything else. Nothing is frozen and densification runs as in any run, so the result is
still the inpainted views' 3D consensus, only reached in fewer steps.
"""

from __future__ import annotations

import copy
import dataclasses

import torch

from engine.io.gaussians import PARAM_NAMES, Gaussians
from engine.io.ply_io import load_ply
from engine.train.config import TrainConfig


def within_cap(gaussians: Gaussians, cap: int) -> Gaussians:
    """At most `cap` Gaussians, the most opaque: with a budget MCMC only relocates, never removes, so a start
    above the cap would stay above it."""
    n = len(gaussians["means"])
    if cap <= 0 or n <= cap:
        return gaussians
    keep = torch.topk(gaussians["opacities"].reshape(n), cap).indices.sort().values
    return {k: v[keep] for k, v in gaussians.items()}


def warm_setup(job, settings: TrainConfig) -> tuple[TrainConfig, dict]:
    """The settings and Trainer plug-ins of a warm start: the removed scene's Gaussians and the base run's
    classifier, every SH band from the first step (the start has them all), and a tenth of the base run's
    steps unless the user gave --steps."""
    config = dataclasses.replace(settings.with_steps(job.short_steps()), sh_degree_interval=1)
    removed = load_ply(job.removed.point_cloud)
    start = within_cap({k: removed[k].float() for k in PARAM_NAMES}, config.max_gaussians)
    return config, {"start": start, "classifier": copy.deepcopy(job.original.classifier)}
