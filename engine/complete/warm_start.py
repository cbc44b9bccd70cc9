"""The warm start of the methods that train a new scene (`--warm`, engine.complete.retrain): the removed scene,
with only what renders into the hole trained (engine.complete.hole_region).

Why a start from the removed scene is honest for Init, Ref and Direct: outside the object's region their
training images are the input images the base run already fitted, so its Gaussians there are what a new run
would relearn; inside the hole they are the removed scene's see-through, which the inpainted images retrain.
Why the rest stays fixed: retrained on the inpainted views it only gets worse (measured on the held-out table:
Init-fsr[warm] below the unfilled hole on three of four scenes, and a blurred capture), and the inpainted views
say nothing new outside the hole.
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from engine.base.errors import InputError
from engine.base.progress import emit
from engine.complete.finetune import hole_gaussians, nearest_identity, reference_views
from engine.complete.hole_region import (
    changeable,
    fit_to_holes,
    hole_bound,
    no_hole,
    nothing_to_train,
    occluding_depths,
    split_at_hole,
)
from engine.formats.layout import InpaintedLayout, RemovedLayout
from engine.inpaint.run import inpainted_dilation
from engine.io.gaussians import PARAM_NAMES, Gaussians, concat
from engine.io.image_io import exr_name, read_depth
from engine.io.masks import dilate, read_masks
from engine.io.ply_io import load_ply
from engine.train.config import TrainConfig

SEED_VIEWS = 3  # the views with the largest holes seed the hole's surface, as FT(3)'s reference views
GRAFT_RING_PX = 2  # a grafted scene's new Gaussians may lie this far past the hole (they cover its edge)


def warm_setup(job, settings: TrainConfig) -> tuple[TrainConfig, dict]:
    """The settings and Trainer plug-ins of a warm start: the removed scene's Gaussians that render into the
    hole, new ones on the hole's surface, the rest fixed; the base run's classifier; every SH band from the
    first step; a tenth of the base run's steps unless the user gave --steps; only views with a hole drawn;
    the budget what the fixed Gaussians leave of the base run's (at least the start)."""
    scene = job.original.scene
    removed = load_ply(job.removed.point_cloud)
    holes, surfaces = _hole_views(job, removed)
    movable, fixed = split_at_hole(removed, changeable(removed, scene, holes, surfaces))
    seeds = _seeds(job, holes, surfaces, removed, settings.sh_degree)
    start = concat(movable, seeds)
    views = [i for i in scene.train if holes[i].any()]
    idle = nothing_to_train(start, views, job.holes.root)
    if idle:
        return _idle_setup(job, settings, removed, idle)
    budget = settings.max_gaussians
    cap = max(budget - len(fixed["means"]), len(start["means"])) if budget > 0 else 0
    config = dataclasses.replace(settings.with_steps(job.short_steps()), sh_degree_interval=1, max_gaussians=cap)
    return config, {"start": start, "fixed": fixed, "views": views,
                    "classifier": copy.deepcopy(job.original.classifier)}


def no_hole_setup(job, settings: TrainConfig) -> tuple[TrainConfig, dict]:
    """The idle run where no training view has a hole, for FT (whose finetune_setup found none): as a warm
    start's, the removed scene whole and no step."""
    return _idle_setup(job, settings, load_ply(job.removed.point_cloud), no_hole(job.holes.root))


def _idle_setup(job, settings: TrainConfig, removed: Gaussians, why: str) -> tuple[TrainConfig, dict]:
    """A run of no steps whose scene is the removed one, fixed whole (nothing to train, `why`): the completion's
    folder is then what every completion writes (run, renders, scores, turntable) and the report says why. Every
    SH band from step 0 (sh_degree_interval 0): the removed scene renders as removal left it."""
    emit("note", stage="complete", note=why)
    job.notes["nothing_to_train"] = why
    config = dataclasses.replace(settings, steps=0, sh_degree_interval=0, max_gaussians=0)
    nothing = split_at_hole(removed, np.zeros(len(removed["means"]), bool))[0]
    return config, {"start": nothing, "fixed": removed, "views": list(job.original.scene.train),
                    "classifier": copy.deepcopy(job.original.classifier)}


def _hole_views(job, removed: Gaussians) -> tuple[dict[int, np.ndarray], dict[int, np.ndarray]]:
    """Each view's hole as the inpainting filled it (its dilation) and the depth at which `removed` (the removed
    scene) hides what lies behind (hole_region.occluding_depths)."""
    scene = job.original.scene
    if not job.holes.root.is_dir():
        raise InputError(f"{job.holes.root} missing: run `python -m engine holes` on the run first")
    holes = read_masks(job.holes.root, scene.cameras, inpainted_dilation(job.inpainted))
    return holes, occluding_depths(removed, scene.cameras, job.device)


def graft(job) -> dict:
    """A scene trained from scratch (--no-warm) kept to the hole: its Gaussians that render into the hole (grown by
    GRAFT_RING_PX) alone, over the removed scene's that render anywhere else (the warm start's split by centres,
    engine.complete.hole_region), with the base run's classifier, written over the run's point_cloud.ply. So outside
    the hole every view renders nearly as the removed scene does (tiny runs of training seeds 0-4: worst view
    38.2-43.4 dB, mean 47.4-48.9, against 16.6-20.0 and 23.7-24.5 for the whole new scene), while the hole is what
    the new scene learned from the inpainted views. Without the ring the hole's edge lost its new Gaussians and the
    fill scored below the unfilled hole in the training views; whole Gaussians instead of centres left too few new
    ones inside the hole, so those wider than the hole are shrunk to it instead (hole_region.fit_to_holes). The
    removed scene's Gaussians kept are all but those the completion may change (hole_region.changeable: a wide one
    centred in the hole stays, as it renders past it too). A resumed run grafts again what its last checkpoint
    writes back (the trained scene), so the result is the same."""
    from engine.io.ply_io import save_classifier

    scene, layout = job.original.scene, job.out.run
    removed, trained = load_ply(job.removed.point_cloud), load_ply(layout.point_cloud)
    holes, surfaces = _hole_views(job, removed)
    fixed = split_at_hole(removed, changeable(removed, scene, holes, surfaces))[1]
    inside = _kept_to_holes(trained, scene, holes, surfaces)
    if len(inside["means"]):
        inside["identity"] = nearest_identity(inside["means"], removed)
    _write_scene(layout.point_cloud, concat(fixed, inside))
    save_classifier(layout.classifier, job.original.classifier)
    return {"new_in_hole": len(inside["means"]), "new_elsewhere": len(trained["means"]) - len(inside["means"]),
            "removed_kept": len(fixed["means"]), "gaussians": len(fixed["means"]) + len(inside["means"])}


def confine(job, warm: bool) -> dict:
    """A run that trained beside fixed Gaussians (`warm` Init, Ref and Direct: the removed scene but what a
    completion may change, hole_region.changeable; FT: the whole removed scene), its trained part kept to the hole
    after training as the graft keeps a scratch scene's: what renders into the hole alone (grown by GRAFT_RING_PX),
    those grown wider than it shrunk into it, the rest dropped. The run's scene holds the fixed Gaussians first
    (engine.train.trainer), and they stay as they are. Why: training moves Gaussians and MCMC adds them near the
    hole, and nothing held them to it in the views no step drew: the held-out test views, and any view a user
    renders. On the statue capture the warm Ref grew its hole's Gaussians from 0 to 143,035 (the removed object's
    share of the budget) and its test views outside the holes fell to 23.9 dB against the removed scene's renders,
    with a streak where the statue stood (5e5ff92, `docs/results/capture/statue.json`)."""
    scene, layout = job.original.scene, job.out.run
    removed, now = load_ply(job.removed.point_cloud), load_ply(layout.point_cloud)
    holes, surfaces = _hole_views(job, removed)
    fixed_count = (int((~changeable(removed, scene, holes, surfaces)).sum()) if warm  # warm_setup's split, again
                   else len(removed["means"]))
    fixed = {k: now[k][:fixed_count].float() for k in PARAM_NAMES}
    trained = {k: now[k][fixed_count:].float() for k in PARAM_NAMES}
    inside = _kept_to_holes(trained, scene, holes, surfaces)
    _write_scene(layout.point_cloud, concat(fixed, inside))
    return {"trained_in_hole": len(inside["means"]), "trained_dropped": len(trained["means"]) - len(inside["means"]),
            "fixed": fixed_count, "gaussians": fixed_count + len(inside["means"])}


def _kept_to_holes(gaussians: Gaussians, scene, holes: dict[int, np.ndarray],
                   surfaces: dict[int, np.ndarray]) -> Gaussians:
    """The `gaussians` whose centres render into the holes grown by GRAFT_RING_PX (they cover the hole's edge) and
    nowhere else, shrunk to fit them where wider (hole_region.hole_bound, fit_to_holes)."""
    grown = {i: dilate(hole, GRAFT_RING_PX) for i, hole in holes.items()}
    bound = split_at_hole(gaussians, hole_bound(gaussians["means"].numpy(), scene, grown, surfaces))[0]
    return split_at_hole(*fit_to_holes(bound, scene, grown))[0]


def _write_scene(path, gaussians: Gaussians) -> None:
    """`gaussians` over the run's point_cloud.ply, whole or not at all."""
    from engine.io.ply_io import save_ply

    partial = path.with_name(".kept.ply")
    save_ply(partial, gaussians)
    partial.replace(path)


def _seeds(job, holes: dict[int, np.ndarray], surfaces: dict[int, np.ndarray], removed: Gaussians,
           sh_degree: int) -> Gaussians:
    """New Gaussians on the hole's surface that render into the hole alone: from the inpainted depth of the
    views with the largest holes, or the removed renders' depth where the inpainting has none (Direct's)."""
    scene = job.original.scene
    refs = reference_views(holes, scene.train, SEED_VIEWS)
    if not refs:
        return split_at_hole(removed, np.zeros(len(removed["means"]), bool))[0]
    inpainted: InpaintedLayout = job.inpainted
    depths = {i: _fill_depth(inpainted, job.removed, scene.cameras[i].name) for i in refs}
    seeds = hole_gaussians(scene, holes, depths, inpainted, sh_degree, job.config.seed, minimum=0)
    keep = hole_bound(seeds["means"].numpy(), scene, holes, surfaces)
    seeds = split_at_hole(seeds, keep)[0]
    if len(seeds["means"]):
        seeds["identity"] = nearest_identity(seeds["means"], removed)
    return seeds


def _fill_depth(inpainted: InpaintedLayout, removed: RemovedLayout, name: str) -> np.ndarray:
    path = inpainted.depth / exr_name(name)
    return read_depth(path if path.is_file() else removed.depth / exr_name(name))
