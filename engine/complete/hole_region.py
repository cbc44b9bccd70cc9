"""What a completion may change: the Gaussians that render into the hole and nowhere else.

Why: a completion that retrains the whole removed scene on the inpainted views relearns what removal had left
right, and blurs it (the statue capture's buildings were sharp after `remove` and soft after `complete`); the
inpainted views are only new inside the hole. So a completion trains the Gaussians of its hole alone:

- a Gaussian of the removed scene is *movable* when its centre falls inside the (dilated) hole of at least one
  view, and in every view where it lies in front of the camera, inside the image and not hidden behind the
  removed scene's surface there, inside that view's hole. Everything else is the Trainer's `fixed` set:
  rendered every step, never changed (engine.train.trainer), so outside the holes every view renders as the
  removed scene does;
- new Gaussians seed the hole's surface (engine.complete.finetune.hole_gaussians: the inpainted depth of the
  views with the largest holes, or the removed renders' depth where an inpainting has none), kept by the same
  test, because densification only grows from what is already movable.

Where the removed scene's surface hides a Gaussian in a view (its depth beyond the rendered depth by more than
`HIDDEN_SLACK`), that view says nothing about it: the hole's back wall is seen through the hole in some views and
hidden in the rest, and only the first say where it renders.
"""

from __future__ import annotations

import numpy as np
import torch

from engine.base.errors import InputError
from engine.capture.scene import Scene
from engine.formats.cameras import project, sample_nearest
from engine.io.gaussians import PARAM_NAMES, Gaussians

HIDDEN_SLACK = 1.05  # a Gaussian this much deeper than the view's rendered surface is hidden there
NEAR = 1e-3


def hole_bound(means: np.ndarray, scene: Scene, holes: dict[int, np.ndarray],
               depths: dict[int, np.ndarray], widths: np.ndarray | None = None) -> np.ndarray:
    """Which `means` (N, 3) render into the holes (view -> bool mask) and nowhere else (see the module
    docstring); `depths` are the removed scene's rendered depths of the same views. With `widths` (N,: each
    Gaussian's footprint, 3 sigma of its largest scale) also only those no wider than the hole their centre falls
    in, in every view where it falls in one: the hole's equivalent diameter (of a disc of its area). Why: a scene
    trained from scratch holds Gaussians far wider than any hole; grafted by their centres, one 107 px wide at
    opacity 0.97 in a 96 px view hazed every view (the tiny CPU run once the holes took the band the photos
    contradict: worst view outside the holes 22.1 dB, 32.8 without the new Gaussians over 40 px)."""
    inside_some = np.zeros(len(means), bool)
    outside_any = np.zeros(len(means), bool)
    fits = np.ones(len(means), bool)
    for i, hole in holes.items():
        camera = scene.cameras[i]
        u, v, z = project(camera, means)
        in_hole, in_image = sample_nearest(hole, u, v)
        in_image &= z > NEAR
        surface, _ = sample_nearest(depths[i], u, v)
        shown = ~(np.isfinite(surface) & (surface > 0)) | (z <= surface * HIDDEN_SLACK)
        inside_some |= in_image & in_hole
        outside_any |= in_image & ~in_hole & shown
        if widths is not None:
            across = 2.0 * np.sqrt(hole.sum() / np.pi)
            fits &= ~(in_image & in_hole) | (2.0 * widths * camera.fx / np.maximum(z, NEAR) <= across)
    return inside_some & ~outside_any & fits


def footprint_widths(gaussians: Gaussians) -> np.ndarray:
    """(N,) each Gaussian's footprint in world units: 3 sigma of its largest scale (hole_bound's `widths`)."""
    return 3.0 * torch.exp(gaussians["scales"]).max(dim=-1).values.numpy()


def split_at_hole(gaussians: Gaussians, movable: np.ndarray) -> tuple[Gaussians, Gaussians]:
    """(movable, fixed) parts of `gaussians` by the boolean `movable`."""
    keep = torch.as_tensor(movable)
    return ({k: gaussians[k][keep].float() for k in PARAM_NAMES},
            {k: gaussians[k][~keep].float() for k in PARAM_NAMES})


def check_movable(start: Gaussians, holes_root) -> None:
    if len(start["means"]) == 0:
        raise InputError(f"nothing renders into the holes in {holes_root}: no Gaussian to train there (check "
                         "the hole masks, or keep the removed scene as it is)")
