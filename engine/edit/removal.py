"""Stage 2: delete an object's Gaussians, by identity (Gaussian Grouping) or by a 3D box.

By identity: softmax(classifier(identity)) per Gaussian, removed where the object's probability exceeds
`threshold`. Gaussian Grouping then adds every Gaussian inside the convex hull of the selection, which can
swallow the table the object stands on; here the optional clean-up is the object's *visual hull* from the
scene's masks instead: a Gaussian goes when it projects into the object's mask (dilated by a few pixels)
in nine in ten of the training views that have it in frame. A table Gaussian seen beside the object from
its side stays; what only a few grazing views saw through a gap under the object (the dark cavity under a
toy's body) goes with it. Then the pieces left loose where the object was (engine.edit.loose) go too, and
the faint Gaussians that render only inside the object's region (engine.edit.faint: its translucent shell).

The output folder (default RUN/removed) holds the remaining Gaussians as a standard PLY, renders of every
view (images/, depth/), the object's mask per view (masks/, the region stage 3 looks for holes in),
removal.json (selection counts, config, PSNR against gt/ on test views outside the true hole, and on the
revealed part of the object's region that other views saw: remnants of the object show there), and a
contact sheet.

With `effects` (the default) what the object did around itself goes too: its cast shadow (engine.edit.effects),
then the darkening under and beside it (engine.edit.contact_shade), then the crater grazing views built under it
(engine.edit.underside), and where no support was built under it at all, a flat patch of it is laid (find_unbuilt).
The Gaussians in them are relit (the crater repainted) before
anything is rendered, so removed/ and every later stage see the scene without them, and removed/effects/
holds each view's effect mask (255 = relit or repainted), effects.json (light direction, gains, why no shadow was found,
recall and precision against the scene's effects/ where it has them) and a contact sheet. The plane the
object stood on, fitted to the remaining Gaussians, goes into removal.json for the hole masks.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch

from engine.base.device import pick_device
from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir, check_new_output
from engine.base.progress import Progress, emit
from engine.edit.contact_shade import ContactShade, find_contact_shade
from engine.edit.diffuse import diffuse_support
from engine.edit.effects import (
    EffectsConfig,
    Samples,
    ShadowSearch,
    brighten,
    effect_mask,
    effect_weights,
    find_shadow,
    relight,
    residual_gain,
)
from engine.edit.faint import faint_inside
from engine.edit.loose import loose_pieces
from engine.edit.support_plane import Footprint, object_core, object_support
from engine.edit.underside import SOLID, Underside, find_unbuilt, find_underside, paint
from engine.formats.cameras import mean_up
from engine.formats.layout import EffectsLayout, RemovedLayout
from engine.geometry.scene_geometry import ProposalConfig, camera_frame, find_supports, unsliced
from engine.io.extent import inside_box
from engine.io.gaussians import Gaussians, concat
from engine.io.image_io import exr_name, write_depth, write_png
from engine.io.masks import dilate
from engine.io.ply_io import save_ply
from engine.io.visibility import inside_visual_hull
from engine.metrics.image_metrics import masked_psnr, mean_and_worst
from engine.pictures.preview import label, overlay
from engine.render.render_views import render_pictures
from engine.train.trained_run import TrainedRun, load_run

RESIDUAL_ROUNDS = 4  # relights of the cast shadow after the first, at most (_relit_to_gain)
RESIDUAL_DONE = 1.02  # ... stopping once its dark samples lack less than this of the gain in every channel
# times the darkening under and beside the object is looked for and relit, each on the renders after the last: a
# pixel blends relit Gaussians with ones left alone, so one relight leaves part of it (tiny CPU runs, PSNR outside
# the true hole, 1 -> 3 rounds: livingroom s7 29.02 -> 29.18, s8 28.88 -> 29.02, wallmount s7 26.86 -> 26.95,
# statue s7 27.90 -> 27.94 dB)
CONTACT_ROUNDS = 3


@dataclass
class RemovalConfig:
    """Which Gaussians go with the object, and whether its effects go too (docs/BENCHMARKS.md, "Decisions")."""

    run: str = ""  # the training run
    object: str = ""  # id or name from the scene's objects.json; empty with --box
    box: list[float] = field(default_factory=list)  # x0 y0 z0 x1 y1 z1 (world), instead of an object
    threshold: float = 0.3  # object probability above which a Gaussian is removed (Gaussian Grouping's)
    hull: bool = True  # also remove Gaussians inside the object's visual hull (needs masks)
    hull_dilate: int = 2  # px added around the masks for the hull test
    hull_share: float = 0.9  # share of the views framing a Gaussian whose mask it must fall in, for the hull
    loose: bool = True  # --object: also remove the pieces left loose where it was (engine.edit.loose)
    faint: bool = True  # --object: also the faint Gaussians left that render only in its region (engine.edit.faint)
    effects: bool = True  # also undo the object's shadow and darkening (relight them), write removed/effects
    contact_most: float = EffectsConfig.contact_most  # the darkening's largest gain (sRGB); 1 or less: not relit
    unbuilt_cover: float = EffectsConfig.unbuilt_cover  # support cover (alpha) under which a patch of it is laid
    patch_seen_through: bool = EffectsConfig.patch_seen_through  # a patch also where the training views see through
    seen_colour: bool = EffectsConfig.seen_colour  # the patch's colour from the views' renders of the support round it
    soft_edge: bool = EffectsConfig.soft_edge  # relight the cast shadow's penumbra by how dark it is, not all or none
    out: str = ""  # default RUN/removed
    scene: str = ""  # default: the scene named in the run's config.json
    device: str = "auto"  # auto | cuda | cpu


def object_probability(identity: torch.Tensor, classifier: torch.nn.Linear, object_id: int) -> torch.Tensor:
    """(N,) probability of `object_id` for each Gaussian's identity encoding (N, 16)."""
    if object_id >= classifier.out_features:
        raise InputError(f"object id {object_id} is beyond the classifier's {classifier.out_features} classes")
    with torch.no_grad():
        return torch.softmax(classifier(identity.float()), dim=-1)[:, object_id]


def select(run: TrainedRun, config: RemovalConfig) -> tuple[np.ndarray, dict]:
    """(N,) bool Gaussians to remove, and how many each rule picked."""
    means = run.gaussians["means"].numpy()
    if config.box:
        chosen = inside_box(means, config.box)
        return chosen, {"box": int(chosen.sum())}
    obj = run.scene.object_by(config.object)
    chosen = (object_probability(run.gaussians["identity"], run.classifier, obj.id) > config.threshold).numpy()
    counts = {"identity": int(chosen.sum())}
    if config.hull and run.scene.masks is not None:
        views = run.scene.train
        masks = [dilate(run.scene.masks[i] == obj.id, config.hull_dilate) for i in views]
        hull = inside_visual_hull(means, [run.scene.cameras[i] for i in views], masks, share=config.hull_share)
        counts["hull_only"] = int((hull & ~chosen).sum())
        chosen |= hull
    return chosen, counts


def other_objects(run: TrainedRun, remaining: Gaussians, target: int | None) -> np.ndarray:
    """(N,) bool over the `remaining` Gaussians: those the identity classifier gives to an object other than the
    background (id 0) and the `target` with probability over 0.5. The effects leave them as they are: they stand
    on the support, and the band around its plane reaches their bases (engine.edit.effects.support_only)."""
    if run.classifier.out_features <= 1:
        return np.zeros(len(remaining["means"]), bool)
    with torch.no_grad():
        best, label = torch.softmax(run.classifier(remaining["identity"].float()), dim=-1).max(dim=-1)
    return ((label != 0) & (label != (-1 if target is None else target)) & (best > 0.5)).numpy()


def _free(run: TrainedRun, removed: np.ndarray, target: int) -> np.ndarray:
    """(N,) bool: the Gaussians off every support plane (a plane through the `removed` ones is no wall) and not
    another object's: what the loose pieces and the faint ones may be taken from."""
    means, frame = run.gaussians["means"].numpy(), camera_frame(run.scene.cameras)
    opacity = torch.sigmoid(run.gaussians["opacities"]).numpy()
    supports = find_supports(means, opacity, frame, ProposalConfig())
    free = unsliced(supports, means, opacity >= ProposalConfig.solid, removed,
                    ProposalConfig.plane_tol * frame.radius).free
    return free & ~other_objects(run, run.gaussians, target)


def keep(gaussians: Gaussians, removed: np.ndarray) -> Gaussians:
    index = torch.from_numpy(~removed)
    return {k: v[index] for k, v in gaussians.items()}


def run_removal(config: RemovalConfig) -> dict:
    """Remove the object (and its shadow), render every view of what remains, and write the output folders
    atomically."""
    if bool(config.box) == bool(config.object):
        raise InputError("give either --object ID_OR_NAME or --box x0 y0 z0 x1 y1 z1")
    config = dataclasses.replace(config, box=[float(v) for v in config.box])
    run = load_run(config.run, config.scene or None)
    out = Path(config.out) if config.out else run.layout.removed.root
    check_new_output(out)
    device = pick_device(config.device)
    removed, counts = select(run, config)
    scene = run.scene
    obj = scene.object_by(config.object) if config.object else None
    up = mean_up(np.stack([c.R for c in scene.cameras]))
    core = object_core(keep(run.gaussians, ~removed), up)
    # a box removes exactly what it holds
    free = _free(run, removed, obj.id) if obj is not None and (config.loose or config.faint) else None
    if config.loose and free is not None:
        frame = camera_frame(scene.cameras)
        loose = loose_pieces(run.gaussians["means"].numpy(), removed, free, core, ProposalConfig.voxel * frame.radius)
        counts["loose"] = int(loose.sum())
        removed |= loose
    # the object's region: the scene's masks, else the original's rendered labels; for a box, where
    # the removed Gaussians alone cover a pixel (renders only when the masks do not say)
    if obj is not None and scene.masks is not None:
        regions = [scene.masks[i] == obj.id for i in range(len(scene.cameras))]
    else:
        source = run.gaussians if obj is not None else keep(run.gaussians, ~removed)
        regions = [_object_region(scene, i, obj, picture) for i, picture in
                   enumerate(render_pictures(source, scene.cameras, run.sh_degree, device, run.classifier,
                                                    depth=obj is None))]  # a box's region is its depth
    if config.faint and free is not None:
        views = scene.train
        faint = faint_inside(run.gaussians, removed, free, [scene.cameras[i] for i in views],
                             [dilate(regions[i], config.hull_dilate) for i in views], device)
        counts["faint"] = int(faint.sum())
        removed |= faint
    remaining = keep(run.gaussians, removed)
    plane = object_support(remaining["means"].numpy(), core, up)
    footprint = Footprint.of(core, up if plane is None else plane[0])
    # alpha only for --seen-colour (undo_darkening's views' samples; relights re-render colours only and keep it)
    after = list(render_pictures(remaining, scene.cameras, run.sh_degree, device, alpha=config.seen_colour))
    effects, diffuse = None, 0
    if config.effects:
        others = other_objects(run, remaining, obj.id if obj else None)
        remaining, after, effects = _undo_effects(run, remaining, core, plane, regions, after, device, others,
                                                  EffectsConfig(contact_most=config.contact_most,
                                                                unbuilt_cover=config.unbuilt_cover,
                                                                patch_seen_through=config.patch_seen_through,
                                                                seen_colour=config.seen_colour,
                                                                soft_edge=config.soft_edge))
        # last: the support the object hid from many views loses the view-dependence it guessed there (before
        # the effects it changed what they read: tiny CPU statue_s6's unfilled hole -0.19 dB)
        others = np.concatenate([others, np.zeros(effects.laid, bool)])  # the patch laid is support
        remaining, diffuse = diffuse_support(remaining, core, plane, scene.cameras, regions, scene.train, others,
                                             EffectsConfig())
        if diffuse:  # colours only: no surface moved
            after = _rerendered(run, remaining, after, device)
    shadow = effects.search.shadow if effects else None
    with atomic_output_dir(out) as tmp_root:
        tmp = RemovedLayout(tmp_root)
        save_ply(tmp.point_cloud, remaining)
        progress = Progress("removal", len(scene.cameras))
        scores, everywhere, revealed, sheet = [], [], [], []
        for i, (camera, region, picture) in enumerate(zip(scene.cameras, regions, after, strict=True)):
            write_png(tmp.images / camera.name, picture.rgb)
            write_depth(tmp.depth / exr_name(camera.name), picture.depth)
            write_png(tmp.masks / camera.name, region.astype(np.uint8) * 255)
            if i in scene.gt_images and i in scene.holes:  # every view with a truth: training views too
                outside = masked_psnr(picture.rgb, scene.gt_images[i], ~scene.holes[i])
                everywhere.append(outside)
            if i in scene.gt_images and i in scene.holes and i in scene.test:
                scores.append(outside)
                if (region & ~scene.holes[i]).any():
                    revealed.append(masked_psnr(picture.rgb, scene.gt_images[i], region & ~scene.holes[i]))
            if len(sheet) < 6 and i in scene.test:
                sheet.append(np.concatenate([label(scene.images[i], f"{camera.name} input"),
                                             label(overlay(scene.images[i], region), "object region"),
                                             label(picture.rgb, "removed")], axis=1))
            progress.update(i + 1)
        progress.close()
        if sheet:
            write_png(tmp.sheet, np.concatenate(sheet, axis=0))
        report = {"config": dataclasses.asdict(config), "object": dataclasses.asdict(obj) if obj else None,
                  "gaussians_before": int(len(removed)), "removed": int(removed.sum()),
                  "gaussians_after": len(remaining["means"]), "selected_by": counts,
                  "laid": effects.laid if effects else 0,  # Gaussians of the unbuilt support's patch
                  "made_diffuse": diffuse,  # support Gaussians it hid, their view-dependent colour dropped
                  "support_plane": None if plane is None else [*np.round(plane[0], 6).tolist(), round(plane[1], 6)],
                  "footprint": footprint.report() if footprint else None,
                  "shadow": shadow.report() if shadow else None,
                  "psnr_outside_hole": float(np.mean(scores)) if scores else None,
                  "psnr_revealed": float(np.mean(revealed)) if revealed else None, "views_scored": len(scores),
                  "psnr_outside_hole_every_view": mean_and_worst(everywhere)}
        if effects is not None:
            report["effects"] = _write_effects(tmp.effects, scene, remaining, effects, regions, after, device)
        tmp.report.write_text(json.dumps(report, indent=1))
    emit("done", stage="removal", out=str(out), removed=report["removed"],
         psnr_outside_hole=report["psnr_outside_hole"], shadow=report["shadow"])
    return report


@dataclass
class _Effects:
    """What `remove` found the object did around itself and undid: its cast shadow (or why none), the
    darkening under and beside it, and the crater under it."""

    search: ShadowSearch
    contact: ContactShade | None
    underside: Underside | None
    laid: int = 0  # Gaussians of the patch for the support never built under the object, last in the scene

    def weights(self) -> np.ndarray | None:
        """(N,) per remaining Gaussian, the share of an effect it carries (none for the patch's); None where
        nothing was found."""
        shadow, contact, under = self.search.shadow, self.contact, self.underside
        parts = ([effect_weights(shadow.shadowed, shadow.darkness)] if shadow else []) + \
            ([effect_weights(contact.shaded, contact.weight)] if contact else []) + \
            ([effect_weights(under.painted, under.weight)] if under else [])
        return np.concatenate([np.maximum.reduce(parts), np.zeros(self.laid, np.float32)]) if parts else None


def _undo_effects(run: TrainedRun, remaining, core: np.ndarray, plane, regions: list[np.ndarray], after: list,
                  device, others: np.ndarray, config: EffectsConfig) -> tuple[dict, list, _Effects]:
    """Relight the object's cast shadow, then the darkening under and beside it, each judged by the views'
    renders of the scene as it stands, then repaint the crater under it in the relit support's colour, then lay
    a patch where no support was built under it (undo_darkening); the changed Gaussians and their renders
    (depth changed only by the patch). Other objects' Gaussians (`others`) stay as they are."""
    scene = run.scene
    before = _train_samples(scene, after, regions)
    search = find_shadow(remaining, core, plane, before, config, others)
    if search.shadow is not None:
        remaining, after = _relit_to_gain(run, remaining, search.shadow, before, after, regions, device)
        after = _rerendered(run, remaining, after, device, _untrained(scene))  # the rounds rendered the rest
    spared = others if search.shadow is None else others | search.shadow.theirs  # the contact shade leaves them
    cast = None if search.shadow is None else search.shadow.shadowed
    remaining, after, contact, underside, laid = undo_darkening(run, remaining, core, plane, regions, after, device,
                                                                others, config, spared, cast, not search.surrounded)
    return remaining, after, _Effects(search, contact, underside, laid)


def _relit_to_gain(run: TrainedRun, remaining, shadow, before, after: list, regions: list[np.ndarray], device
                   ) -> tuple[Gaussians, list]:
    """`remaining` with the shadow relit until its dark samples brightened by its gain: each round relights by what
    they still lack (residual_gain, read on the training views' renders), up to RESIDUAL_ROUNDS rounds or until
    they lack under RESIDUAL_DONE. Why more than one: a pixel blends relit Gaussians with ones left alone, so each
    round gets part of the way (tiny CPU wallmount: 1.39, 1.13, 1.05, 1.02 asked for; its shadow 11% darker than
    gt/ after one round, 6% after four). In all they relight by at most the gain again: where relighting does not
    reach the dark samples (a wrong light's cast, whose Gaussians hold none of them) each round asks for all of it.
    `shadow.residual` holds the rounds' gains multiplied, `shadow.lacking` what the dark samples still lacked at
    the end. Also `after` with the training views rendered as relit (the last round read them)."""
    remaining, total = relight(remaining, shadow), np.ones(3)
    for done in range(RESIDUAL_ROUNDS + 1):
        relit = _rerendered(run, remaining, after, device, run.scene.train)  # the residual reads training views only
        lacking = residual_gain(shadow, before, _train_samples(run.scene, relit, regions))
        residual = np.minimum(lacking, np.maximum(shadow.gain / total, 1.0))  # in all, at most the gain again
        if np.all(residual < RESIDUAL_DONE) or done == RESIDUAL_ROUNDS:
            break
        remaining, total = relight(remaining, dataclasses.replace(shadow, gain=residual)), total * residual
    shadow.residual, shadow.lacking = total, lacking
    return remaining, relit


def undo_darkening(run: TrainedRun, remaining, core: np.ndarray, plane, regions: list[np.ndarray], after: list,
                   device, others: np.ndarray, config: EffectsConfig, spared: np.ndarray | None = None,
                   cast: np.ndarray | None = None, shade: bool = True
                   ) -> tuple[dict, list, ContactShade | None, Underside | None, int]:
    """What follows the cast shadow: the darkening under and beside the object relit, judged by `after` (the
    renders of `remaining` as it stands), then the crater under it repainted, then a patch laid where no support
    was built under it (underside.find_unbuilt, last in the scene); the changed Gaussians, their renders (each
    view once), what was found, and how many Gaussians the patch laid. `spared` (default `others`): what the
    contact shade leaves as it is, the other objects and the support in their own cast shadows (Shadow.theirs);
    `cast` (bool over `remaining`): the object's own cast shadow, relit (find_contact_shade's `cast`). `shade`
    False: no contact shade, where the object stands in darkness not its own (ShadowSearch.surrounded: a tree's band
    through it). Held-out statue_s100 on one H200, Ref-telea against the unfilled hole: -3.43 dB with it off
    (418ab7e), -6.11 with it on and the band's cells relit to the band's level (352a36e, measured at dd16d65); the
    tiny tuning runs never say 'surrounded', so only the held-out scene has shown the difference.
    Apart so that a study of the shadow's relight can finish its variants exactly as removal does."""
    contact = None
    # what one relight leaves of it is looked for again, as the shadow's is
    for _ in range(CONTACT_ROUNDS if shade and config.contact_most > 1 else 0):
        # the regions too: what the views saw under an overhang shows inside them in the removed renders
        shown = _train_samples(run.scene, after, [np.zeros_like(region) for region in regions])
        found = find_contact_shade(remaining, core, plane, shown, config, others=others if spared is None else spared,
                                   cast=cast)
        if found is None:
            break
        contact, step = (found, found.gains) if contact is None else contact.joined(found, config.contact_most)
        remaining = brighten(remaining, found.shaded, step)
        after = _rerendered(run, remaining, after, device, run.scene.train)  # the next round reads these only
    # the support where the training views render it whole (a faint rim shows darker over black)
    shown = _train_samples(run.scene, after, [p.alpha < SOLID for p in after]) if config.seen_colour else None
    underside = find_underside(remaining, core, plane, config, others, shown)
    if underside is not None:
        remaining = paint(remaining, underside)
    train = run.scene.train  # and where the training views see through the support: their depth
    views = ([run.scene.cameras[i] for i in train], [after[i].depth for i in train]) \
        if config.patch_seen_through else None
    patch = find_unbuilt(remaining, core, plane, config, others, shown, views)
    if patch is not None:  # last in the scene; it moves surfaces, so every view with its depth
        remaining = concat(remaining, patch)
        after = list(render_pictures(remaining, run.scene.cameras, run.sh_degree, device))
    elif underside is not None:
        after = _rerendered(run, remaining, after, device)  # every view, once both are done
    elif contact is not None:  # its last round rendered the training views
        after = _rerendered(run, remaining, after, device, _untrained(run.scene))
    return remaining, after, contact, underside, 0 if patch is None else len(patch["means"])


def _train_samples(scene, after: list, masks: list[np.ndarray]) -> Samples:
    """The training views' surface samples of the renders `after` (one per view of the scene), outside `masks`;
    the same views, depth and masks give the same samples in the same order (residual_gain relies on it)."""
    train = scene.train
    return Samples.from_views([scene.cameras[i] for i in train], [after[i].rgb for i in train],
                              [after[i].depth for i in train], [masks[i] for i in train])


def _untrained(scene) -> list[int]:
    """The views that are not training views (the test views, which the relights' rounds do not read)."""
    train = set(scene.train)
    return [i for i in range(len(scene.cameras)) if i not in train]


def _rerendered(run: TrainedRun, gaussians, after: list, device, views: list[int] | None = None) -> list:
    """`after` with its colours rendered again from `gaussians` (relighting moves no surface): in `views` only
    where a step reads no others (default every view); the rest keep their old colours: rendering every view is
    most of a removal's time on a CPU, and four colour changes each rendering them all would repeat it four times."""
    views = list(range(len(after))) if views is None else views
    new = render_pictures(gaussians, [run.scene.cameras[i] for i in views], run.sh_degree, device, depth=False)
    out = list(after)
    for i, picture in zip(views, new, strict=True):
        out[i] = dataclasses.replace(after[i], rgb=picture.rgb)
    return out


def _write_effects(out: EffectsLayout, scene, gaussians, effects: _Effects, regions: list[np.ndarray],
                   after: list, device) -> dict:
    """removed/effects: each view's effect mask (the relit shadow and darkening, the repainted crater where it
    was darker), effects.json (with what the shadow search weighed, and recall and precision over every view
    the scene has exact effects for: the masks are a 3D estimate drawn into each view, and the truth comes
    from gt/, which nothing here reads; the benchmark's scenes have it for their test views only) and a
    contact sheet (an empty mask per view
    where nothing was found, so later stages need not ask)."""
    weights = effects.weights()
    recall, precision, sheet = [], [], []
    out.root.mkdir()
    progress = Progress("effects", len(scene.cameras))
    for i, camera in enumerate(scene.cameras):
        mask = (effect_mask(gaussians, weights, camera, device) if weights is not None
                else np.zeros((camera.height, camera.width), dtype=bool))
        write_png(out.mask(camera.name), mask.astype(np.uint8) * 255)
        if i in scene.effects:
            estimate, truth = mask & ~dilate(regions[i], 1), scene.effects[i]
            both = int((estimate & truth).sum())
            if truth.sum():
                recall.append(both / int(truth.sum()))
            if estimate.sum():
                precision.append(both / int(estimate.sum()))
        if len(sheet) < 4 and i in scene.test:
            panels = [label(overlay(scene.images[i], mask, (255, 160, 0)), f"{camera.name} effects"),
                      label(after[i].rgb, "removed, relit")]
            if i in scene.effects:
                panels.append(label(overlay(scene.images[i], scene.effects[i], (0, 255, 0)), "true effects"))
            sheet.append(np.concatenate(panels, axis=1))
        progress.update(i + 1)
    progress.close()
    if sheet:
        write_png(out.sheet, np.concatenate(sheet, axis=0))
    shadow = effects.search.shadow
    report = {"shadow": shadow.report() if shadow else None, "search": effects.search.report(),
              "contact": effects.contact.report() if effects.contact else None,
              "underside": effects.underside.report() if effects.underside else None,
              "unbuilt_support_laid": effects.laid,
              "recall": float(np.mean(recall)) if recall else None,
              "precision": float(np.mean(precision)) if precision else None, "views_scored": len(recall)}
    out.report.write_text(json.dumps(report, indent=1))
    return report


def _object_region(scene, i: int, obj, picture) -> np.ndarray:
    """The object's pixels in view i: from the masks, else from the render (labels, or a box's coverage)."""
    if obj is None:
        return np.isfinite(picture.depth)
    if scene.masks is not None:
        return scene.masks[i] == obj.id
    return picture.labels == obj.id
