"""Stage 3: depth-guided hole masks (3DGIC's idea, without the published code's two bugs).

For each view, the candidate pixels are the removed object's region (removed/masks). Each is lifted to the
surface the *removed* scene renders there (removed/depth) and tested against every training view: the point
counts as seen when it lies in front of the view (z > 0), inside its frame, not behind the surface that view
shows once the object is gone (removed/depth of that view, within a relative tolerance), and not inside that
view's object region (3DGIC's background-only source pixels): where the object touches its support the depths
of the two differ by less than any tolerance, so the masks decide. A pixel no view sees is hole. This is
backward warping (engine.io.visibility, the test the scene generator uses for its exact holes/, there without
masks): no forward-splatting pinholes, no last-write-wins, and the depth compared is the point's z in the
testing view, not the source view's depth value. Pixels where the removed scene renders no surface (alpha
below 0.5: the unseen underside of the object was never reconstructed) are hole as well; the generator's exact
test counts them as seen, since for it an infinite depth is open sky.

Why the training views' depth is the removed scene's and not the whole scene's: outside the object's masks a
view shows the background, but a render of the whole scene spreads the object's Gaussians a pixel or two past
its silhouette and across thin gaps (the tabletop toy's body over the mat between its tracks), so the mat seen
through the gap failed the depth test (docs/BENCHMARKS.md, "Decisions"). It also spares a render of every view.

Before warping, rays of the object's region that the removed render lets through the support (the table
under the object was never built, so the render shows its underside, which side views saw) are stopped at
the support plane the removal fitted to the Gaussians around the object (engine.edit.support_plane; fitted to
rendered depth where removal.json has none). Each training view's depth takes the farthest within a pixel per
640 of image width outside the object's region (a render blurs other silhouettes nearer; inside the region the
removed scene looks through to what lay behind, which must not spread), and the tolerance grows beyond the
object's depth (engine.io.visibility).

By default the masks also take what the render shows wrongly under the object, so that the inpainters fill it
rather than the completions learning it (`see_through`): rays the plane stopped whose point on it lies inside the
object's visual hull (the support never built where it stood, seen through), and pixels whose rendered surface
under the object's footprint lies off the plane (a crater or bulge where only grazing views saw the support,
under an overhang). The report scores the unseen part alone against the truth's holes beside the written masks.
Then the band around each hole that the render gets wrong, as the training photos that saw it show
(engine.edit.border: a remnant's edge, the contact shade relit in part), joins it (`border`, a share of the
width): the inpainters read their colours from the hole's border, so a wrong border is filled rather than copied
inwards, and a right one stays as their context. The photos show the object's shadow where `remove` relit it,
so they would call every relit pixel wrong and the band would take the relit shadow beside the footprint; by
default (`border_relit` off) those pixels stay as context. On the hard-sun statue_s30 (GPU) the masks went from
twice the true hole to IoU 0.77 and Ref-coherence in the true hole 20.97 -> 22.23 dB (unfilled 21.29); with
remove's patch where the views see through the support, tiny CPU statues +1.19 / +1.32 dB, livingroom_s11 +0.73,
wallmount even, tabletop -0.31, livingroom_s8 -0.20 (without that patch -1.31: its relit ring was dark and the fill
copied it; docs/BENCHMARKS.md, "Hole masks"). Optional: a margin around each view's object
mask that hides too, and dilation of the result (LaMa wants larger masks; the paper dilates). Measured choices in
docs/BENCHMARKS.md.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from engine.base.device import pick_device
from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import Progress, emit
from engine.edit.border import BORDER_LEVELS, BORDER_SHARE, OCCLUDER_SHARE, band_px, photo_ranges, wrong_border
from engine.edit.removal import RemovalConfig
from engine.edit.support_plane import (
    Footprint,
    off_support,
    removal_footprint,
    removal_plane,
    stop_at_plane,
    support_plane,
)
from engine.formats.cameras import Camera, backproject, mean_up, pixel_grid, project
from engine.formats.layout import HolesLayout, RemovedLayout, RunLayout
from engine.io.image_io import exr_name, read_depth, read_png, write_png
from engine.io.masks import dilate, optional_mask
from engine.io.visibility import DEFAULT_REL_TOL, Array, as_tensor, farthest_nearby, inside_visual_hull, unseen_mask
from engine.metrics.image_metrics import mean_and_worst
from engine.pictures.preview import label, overlay
from engine.train.trained_run import load_run_scene

# A trained render's silhouettes are blurred by about a pixel, so each view's depth is read as the farthest within
# one pixel per this many of image width, outside the object's region (none below 640 px: on tiny CPU runs a pixel
# took a third of the holes; docs/BENCHMARKS.md, "Hole masks").
BLUR_PX_PER_WIDTH = 640
HULL_DILATE_PX, HULL_SHARE = RemovalConfig.hull_dilate, RemovalConfig.hull_share  # see-through's hull: removal's


@dataclass
class HoleConfig:
    """Which object pixels no view saw behind (3DGIC's depth-guided masks) and which the render shows wrongly."""

    run: str = ""  # the training run
    removed: str = ""  # default RUN/removed
    out: str = ""  # default RUN/holes
    scene: str = ""  # default: the scene named in the run's config.json
    rel_tol: float = DEFAULT_REL_TOL  # depth test tolerance, relative to depth
    dilate: int = 0  # px added around each hole afterwards
    support_plane: bool = True  # stop rays that see through the missing support patch at its plane
    occluder_margin: float = 0.0  # band around each view's object region that hides too, x image diagonal
    see_through: bool = True  # also mark object pixels whose render sees through the support the base run never built
    off_support_tol: float = 0.02  # with see_through, also pixels whose support is this far off its plane, x depth
    border: float = BORDER_SHARE  # also the band this wide (x image width) around a hole that the photos contradict
    border_levels: float = BORDER_LEVELS  # 8-bit levels a band pixel may differ from the photos' colour there
    border_relit: bool = False  # the band may take pixels `remove` relit (the photos show them dark: no judge)
    device: str = "auto"  # where every pixel is tested against every training view (engine.io.visibility)


def _under_object(camera: Camera, stopped: np.ndarray, depth: np.ndarray, cameras: list[Camera],
                  masks: list[Array], device: torch.device | None = None) -> np.ndarray:
    """The `stopped` pixels whose point on the plane (at `depth`) lies under the object: inside its visual
    hull (its region in HULL_SHARE of the training views that frame it). A ray through the object's region
    that passes beside the support's edge meets the plane far beyond the object, where nothing is missing:
    on the CPU statue such rays marked the ground behind the slab (written masks' IoU 0.41 for 0.82 unseen)."""
    ys, xs = np.nonzero(stopped)
    u, v = pixel_grid(camera)
    points = backproject(camera, u[ys, xs], v[ys, xs], depth[ys, xs])
    out = np.zeros_like(stopped)
    out[ys, xs] = inside_visual_hull(points, cameras, masks, share=HULL_SHARE, device=device)
    return out


def iou(a: np.ndarray, b: np.ndarray) -> float:
    union = np.logical_or(a, b).sum()
    return float(np.logical_and(a, b).sum() / union) if union else 1.0


def _object_depth(cameras: list[Camera], footprint: Footprint | None, depths: list[np.ndarray],
                  regions: list[np.ndarray]) -> float | None:
    """The object's median depth in the training views: up to it the depth test's tolerance is rel_tol,
    beyond it that grows with depth (engine.io.visibility.seen_by_any). Its footprint's centre where `remove`
    found one (4-9% beyond the whole scene's rendered depth over the object's region, which holes used to render,
    and the same unseen IoU to 0.001 on all six 640x480 base runs measured), else the removed scene's depth
    there, which lies behind the object and so errs tight."""
    if footprint is not None:
        return float(np.median([project(camera, footprint.centre[None])[2][0] for camera in cameras]))
    values = np.concatenate([d[r & np.isfinite(d)] for d, r in zip(depths, regions, strict=True)])
    return float(np.median(values)) if values.size else None


def run_holes(config: HoleConfig) -> dict:
    scene, layout = load_run_scene(config.run, config.scene or None), RunLayout(config.run)
    removed = RemovedLayout(config.removed) if config.removed else layout.removed
    out = Path(config.out) if config.out else layout.holes.root
    if not removed.report.is_file():
        raise InputError(f"{removed.report} missing: run `python -m engine remove --run {config.run} ...` first")
    train_cameras = [scene.cameras[i] for i in scene.train]
    regions = [read_png(removed.masks / camera.name, "mask", camera.size) > 0 for camera in scene.cameras]
    train_regions = [regions[i] for i in scene.train]
    # what each training view shows once the object is gone (remove rendered every view)
    seen_depths = [read_depth(removed.depth / exr_name(camera.name)) for camera in train_cameras]
    train_depth = dict(zip(scene.train, seen_depths, strict=True))
    up = mean_up(np.stack([c.R for c in scene.cameras]))
    plane = (removal_plane(removed) or support_plane(train_cameras, train_regions, seen_depths, config.rel_tol, up)
             if config.support_plane else None)
    footprint = removal_footprint(removed)
    near = _object_depth(train_cameras, footprint, seen_depths, train_regions)
    device = pick_device(config.device)
    # what every view is tested against, on the device once: their silhouettes' blur undone, outside the object's
    # region (the masks' business)
    seen_surfaces = [as_tensor(farthest_nearby(depth, camera.width // BLUR_PX_PER_WIDTH, region), device)
                     for depth, camera, region in zip(seen_depths, train_cameras, train_regions, strict=True)]
    # the object's region in each training view: it hid whatever lies behind it there
    occluders = [as_tensor(dilate(regions[i], round(config.occluder_margin * np.hypot(scene.cameras[i].width,
                                                                                   scene.cameras[i].height))), device)
                 for i in scene.train]
    hull_masks = [as_tensor(dilate(regions[i], HULL_DILATE_PX), device) for i in scene.train]
    photos = [(as_tensor(low, device), as_tensor(high, device))  # what was there: the border's judge
              for low, high in photo_ranges([scene.images[i] for i in scene.train])]
    photo_occluders = [as_tensor(dilate(regions[i], band_px(scene.cameras[i].width, OCCLUDER_SHARE)), device)
                       for i in scene.train]
    views, sheet = [], []
    with atomic_output_dir(out) as tmp_root:
        tmp = HolesLayout(tmp_root)
        progress = Progress("holes", len(scene.cameras))
        for i, camera in enumerate(scene.cameras):
            region = regions[i]
            rendered = train_depth[i] if i in train_depth else read_depth(removed.depth / exr_name(camera.name))
            background = rendered if plane is None else stop_at_plane(camera, region, rendered, plane, config.rel_tol)
            # where the removed scene renders no surface at all, nothing is there to show: hole
            unseen = unseen_mask(camera, region, background, train_cameras, seen_surfaces, config.rel_tol,
                                 occluders, near, device) | (region & ~np.isfinite(background))
            see_through = _under_object(camera, region & (background < rendered), background, train_cameras,
                                        hull_masks, device)  # rays the plane stopped where the object stood
            if plane is not None and footprint is not None:  # the support under the footprint rendered off its plane
                see_through |= off_support(camera, region, rendered, plane, footprint, config.off_support_tol)
            unseen_hole = dilate(unseen, config.dilate)
            hole = unseen_hole | dilate(see_through, config.dilate) if config.see_through else unseen_hole
            border = np.zeros_like(hole)
            if config.border > 0 and hole.any():
                rgb = read_png(removed.images / camera.name, size=camera.size)
                border = wrong_border(camera, hole, rgb, rendered, train_cameras, photos, seen_surfaces,
                                      photo_occluders, config.rel_tol, near, band_px(camera.width, config.border),
                                      config.border_levels, device)
                if not config.border_relit:
                    border &= ~optional_mask(removed.effects.mask(camera.name), camera.size)
                hole = hole | border
            write_png(tmp.mask(camera.name), hole.astype(np.uint8) * 255)
            write_png(tmp.unseen(camera.name), unseen_hole.astype(np.uint8) * 255)
            record = {"view": camera.name, "region_px": int(region.sum()), "hole_px": int(hole.sum()),
                      "see_through_px": int((see_through & ~unseen).sum()), "border_px": int(border.sum())}
            if i in scene.holes:
                record["iou_vs_truth"] = iou(hole, scene.holes[i])
                record["unseen_iou_vs_truth"] = iou(unseen_hole, scene.holes[i])
            views.append(record)
            if len(sheet) < 6 and i in scene.test:
                removed_rgb = read_png(removed.images / camera.name)
                sheet.append(np.concatenate([label(overlay(scene.images[i], region), f"{camera.name} region"),
                                             label(overlay(removed_rgb, hole), "hole")]
                                            + ([label(overlay(scene.gt_images[i], scene.holes[i], (0, 255, 0)),
                                                      "true hole")] if i in scene.holes and i in scene.gt_images
                                               else []), axis=1))
            progress.update(i + 1)
        progress.close()
        if sheet:
            write_png(tmp.sheet, np.concatenate(sheet, axis=0))
        scored = [v["iou_vs_truth"] for v in views if "iou_vs_truth" in v]
        unseen_scored = [v["unseen_iou_vs_truth"] for v in views if "unseen_iou_vs_truth" in v]
        with_region = [v for v in views if v["region_px"]]
        report = {"config": dataclasses.asdict(config), "views": views,
                  "mean_iou_vs_truth": float(np.mean(scored)) if scored else None, "views_scored": len(scored),
                  "mean_unseen_iou_vs_truth": float(np.mean(unseen_scored)) if unseen_scored else None,
                  "iou_vs_truth": mean_and_worst(scored), "unseen_iou_vs_truth": mean_and_worst(unseen_scored),
                  "support_plane": None if plane is None else [*plane[0].round(5).tolist(), round(plane[1], 5)],
                  "hole_to_region": (float(np.mean([v["hole_px"] / v["region_px"] for v in with_region]))
                                     if with_region else None)}
        tmp.report.write_text(json.dumps(report, indent=1))
    emit("done", stage="holes", out=str(out), mean_iou_vs_truth=report["mean_iou_vs_truth"],
         mean_unseen_iou_vs_truth=report["mean_unseen_iou_vs_truth"])
    return report
