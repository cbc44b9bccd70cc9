"""Objects for a run that has no ground-truth masks (a user's capture, a splat trained elsewhere): the
Gaussians grouped into objects after training, written to RUN/segments/ and used by every later stage.

Three ways, one artefact (engine.formats.layout.SegmentsLayout): per-Gaussian object ids (ids.npy, 0 =
background), objects.json (id, name, 3D box, Gaussians) and per-view instance-id PNGs rendered from the ids
(masks/<image name>.png), plus segments.json (how they were made).

- from user masks (`--from-masks DIR`): per-view masks whose ids need not agree across views (what SAM's
  automatic mask generator or any 2D tool gives). Each Gaussian centre that a training view sees (in frame,
  in front, within `rel_tol` of the rendered depth) takes the id under it; a view's segment joins the object
  that most of its Gaussians already belong to (at least `join`), else it starts a new one; each Gaussian
  finally takes the object it was seen in most often (id 0, unlabelled, counts as background). Training-free:
  seconds.
- automatic (`--auto`): proposals from the geometry (engine.segment.proposals): what rests on or hangs from the
  capture's support planes, split by 3D connectivity; then the subject, the object the capture is about, from
  salient-object votes across views (engine.segment.saliency_votes), named object_1.
- from a selection (`--box`, `--indices` for the proxy points a user selected in Blender, or `--point U V
  --view IMAGE`, a click in one photo): those Gaussians become one more object beside those found so far.

When RUN/segments/ exists, engine.train.trained_run loads the run with these objects, masks and identities
(the identities one-hot over the objects, the classifier their identity map), so `remove --object NAME`,
hole masks, inpainting, completion and Blender's Outliner work as on a generated scene. Gaussian Grouping's
identity has 16 dimensions, so a run holds at most 15 objects besides the background (the largest kept).
"""

from __future__ import annotations

import json
import shutil
from dataclasses import asdict, dataclass, field
from pathlib import Path

import cv2
import numpy as np
import torch

from engine.base.device import pick_device
from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import emit, say
from engine.capture.scene import Scene, SceneObject
from engine.formats.cameras import Camera, backproject, project, sample_nearest
from engine.formats.checks import read_json
from engine.formats.layout import RunLayout, SegmentsLayout
from engine.formats.splat_ply import IDENTITY_DIM, SH_C0
from engine.geometry.scene_geometry import (
    Frame,
    ProposalConfig,
    Supports,
    camera_frame,
    find_supports,
    level_band,
    unsliced,
)
from engine.io.extent import bounding_box, inside_box
from engine.io.gaussians import Gaussians
from engine.io.image_io import read_png, write_png
from engine.pictures.preview import colorize_ids, label
from engine.render.rasterize import CameraTensors, render
from engine.render.render_views import render_depths
from engine.segment.proposals import propose
from engine.segment.saliency_votes import VoteConfig, salient_votes, subject, voting_views, weak_evidence
from engine.segment.salient import SalientNet
from engine.train.segment_objects import identity_of, read_segment_objects

MAX_OBJECTS = IDENTITY_DIM - 1


@dataclass
class SegmentConfig(VoteConfig, ProposalConfig):
    run: str = ""  # the training run
    auto: bool = False  # proposals from the geometry alone (engine.segment.proposals)
    from_masks: str = ""  # a folder of per-view instance-id PNGs named like the images (0 = unlabelled)
    box: list[float] = field(default_factory=list)  # x0 y0 z0 x1 y1 z1: the Gaussians inside become an object
    indices: str = ""  # a .npy or text file of Gaussian indices (Blender's selected proxy points): one object
    point: list[float] = field(default_factory=list)  # U V: a click (pixels of the run's --view image): its object
    view: str = ""  # --point: the image name the click is in
    name: str = ""  # --box/--indices/--point: the object's name (default object_<id>)
    replace: bool = False  # --auto/--from-masks: replace the objects found before (kept for --restore)
    restore: bool = False  # bring back the objects the last segment replaced or extended (again: redo)
    rel_tol: float = 0.03  # a Gaussian is seen when its depth is within this fraction of the rendered depth
    join: float = 0.5  # a segment joins the object that holds at least this fraction of its Gaussians
    min_gaussians: int = 20  # smaller objects go to the background (--from-masks: unless named in min_views views)
    min_views: int = 3  # --from-masks: an object the masks name in this many views stays, however few Gaussians
    # it holds (the tiny livingroom's small objects: 11-17 Gaussians each, named in 5-7 of 7 views)
    out: str = ""  # default RUN/segments
    device: str = "auto"  # auto | cuda | cpu

    def __post_init__(self) -> None:
        self.box = [float(v) for v in self.box]  # saved in segments.json
        self.point = [float(v) for v in self.point]

    @property
    def adds(self) -> bool:
        """--box, --indices and --point add one object to the run's segments; --auto and --from-masks make them
        anew."""
        return bool(self.box or self.indices or self.point)


def lift_masks(means: np.ndarray, cameras: list[Camera], masks: list[np.ndarray], depths: list[np.ndarray],
               rel_tol: float, join: float) -> tuple[np.ndarray, dict, np.ndarray]:
    """(N,) object id per Gaussian (0 = background) from per-view masks with unassociated ids, stats, and per
    object id the number of views whose masks named it (a segment that started or joined it): how steady it is."""
    n = len(means)
    current = np.full(n, -1, np.int64)  # the object a Gaussian last joined (-1: none yet)
    observations: list[np.ndarray] = []  # codes gaussian * stride + object
    named: list[int] = []  # the object each segment started or joined, per segment
    stride, next_id, segments, joined = 1 << 20, 1, 0, 0
    for camera, mask, depth in zip(cameras, masks, depths, strict=True):
        u, v, z = project(camera, means)
        seen_depth, inside = sample_nearest(depth, u, v)
        local, _ = sample_nearest(mask, u, v)
        seen = inside & (z > 0) & (np.abs(z - seen_depth) <= rel_tol * np.abs(z))
        objects = np.zeros(n, np.int64)
        for given in np.unique(local[seen]):
            if given == 0:
                continue
            members = np.flatnonzero(seen & (local == given))
            known = current[members][current[members] > 0]
            segments += 1
            if len(known):
                best = np.bincount(known).argmax()
                if (known == best).sum() >= join * len(members):
                    objects[members], joined = best, joined + 1
                    named.append(int(best))
                    continue
            objects[members], next_id = next_id, next_id + 1
            named.append(next_id - 1)
        labelled = seen & (objects > 0)
        current[labelled] = objects[labelled]
        observations.append(np.flatnonzero(seen) * stride + objects[seen])
    ids = _mode(np.concatenate(observations) if observations else np.zeros(0, np.int64), n, stride)
    return ids, {"segments": segments, "joined": joined, "objects_found": next_id - 1}, \
        np.bincount(np.asarray(named, np.int64), minlength=next_id)


def _mode(codes: np.ndarray, n: int, stride: int) -> np.ndarray:
    """Per Gaussian, the object it was seen in most often (0 where never seen)."""
    ids = np.zeros(n, np.int64)
    if not len(codes):
        return ids
    pairs, counts = np.unique(codes, return_counts=True)
    gaussian, obj = pairs // stride, pairs % stride
    order = np.lexsort((-counts, gaussian))  # per Gaussian, the most frequent first
    first = np.unique(gaussian[order], return_index=True)[1]
    ids[gaussian[order][first]] = obj[order][first]
    return ids


def renumber(ids: np.ndarray, min_gaussians: int, first: int | None = None,
             steady: np.ndarray | None = None) -> np.ndarray:
    """Objects by size, largest first, as 1..K (K <= MAX_OBJECTS), `first` (the subject) before all; small
    (fewer than `min_gaussians`, unless `steady`, bool per id: named in enough views) or surplus ones become
    background."""
    sizes = np.bincount(ids)
    keep = set() if steady is None else set(np.flatnonzero(steady).tolist())
    order = [i for i in np.argsort(-sizes, kind="stable")
             if i != 0 and sizes[i] > 0 and (sizes[i] >= min_gaussians or i in keep)]
    if first is not None and first in order:
        order.remove(first)
        order.insert(0, first)
    order = order[:MAX_OBJECTS]
    table = np.zeros(len(sizes), np.int64)
    table[order] = np.arange(1, len(order) + 1)
    return table[ids]


def instance_masks(gaussians: Gaussians, ids: np.ndarray, cameras: list[Camera], sh_degree: int,
                   device: torch.device) -> list[np.ndarray]:
    """Per view, the object id whose Gaussians dominate each pixel (0 where little is rendered)."""
    count = int(ids.max()) if len(ids) else 0
    identity, classifier = identity_of(ids, count)
    moved = {k: v.to(device) for k, v in {**gaussians, "identity": identity}.items()}
    classifier = classifier.to(device)
    masks = []
    with torch.no_grad():
        for camera in cameras:
            out = render(moved, CameraTensors.from_camera(camera, device), sh_degree, classifier=classifier,
                         depth=False)
            label = out.logits.argmax(-1)
            masks.append(torch.where(out.alpha > 0.5, label, 0).to(torch.uint8).cpu().numpy())
    return masks


def run_segment(run, config: SegmentConfig) -> dict:
    """Write RUN/segments/ for a loaded run (engine.train.trained_run.TrainedRun). --auto and --from-masks
    ignore the run's objects; --box and --indices add one to the segments found so far."""
    if config.restore:
        return restore_segments(run.layout)
    if sum(map(bool, (config.auto, config.from_masks, config.box, config.indices, config.point))) != 1:
        raise InputError("give one of --auto, --from-masks DIR, --box x0 y0 z0 x1 y1 z1, --indices FILE, "
                         "--point U V --view IMAGE or --restore")
    means = run.gaussians["means"].numpy()
    out = SegmentsLayout(config.out) if config.out else run.layout.segments
    if not (config.adds or config.replace) and out.root.exists() and any(out.root.iterdir()):
        raise InputError(f"{out.root} holds the objects found before: pass --replace (they are kept for "
                         "--restore) or another --out")
    device = pick_device(config.device)
    if config.adds:
        ids, objects, stats = _add_selection(run, means, config, device)
    else:
        first, steady = None, None
        if config.from_masks:
            ids, stats, named = _from_masks(run, means, config, device)
            steady = named >= config.min_views
        else:
            opacity = torch.sigmoid(run.gaussians["opacities"]).numpy()
            frame = camera_frame(run.scene.cameras)
            supports = find_supports(means, opacity, frame, config)
            ids, stats = propose(means, opacity, frame, supports, config)
            if config.salient:
                ids, first, votes = _salient_subject(run, ids, opacity, frame, supports, config, stats, device)
                stats.update(votes)
        ids = renumber(ids, config.min_gaussians, first, steady)
        objects = [SceneObject(int(i), f"object_{i}", False) for i in range(1, int(ids.max(initial=0)) + 1)]
        if config.auto and objects:
            stats["subject_share"] = round(float((ids == 1).mean()), 4)  # object_1's share of the scene's Gaussians
            stats["solid_share"] = round(float((opacity >= config.solid).mean()), 4)
            stats["test_psnr"] = _test_psnr(run.layout)
            stats["weak_evidence"] = weak_evidence(stats) if config.salient else []
            for reason in stats["weak_evidence"]:
                say(f"segment --auto: {reason}. Look at {out.sheet}; to pick the subject yourself, click it: "
                    "--point U V --view IMAGE")
    if not objects:
        raise InputError(f"no object found in {run.root} ({stats}): check the masks (0 = unlabelled), or "
                         "select one with --box or --indices")
    masks = instance_masks(run.gaussians, ids, run.scene.cameras, run.sh_degree, device)
    if out.root == run.layout.segments.root and out.objects_json.is_file():  # kept for --restore
        _keep_previous(out.root, run.layout.previous_segments.root)
    with atomic_output_dir(out.root, replace=config.adds or config.replace) as tmp:
        target = SegmentsLayout(tmp)
        np.save(target.ids, ids.astype(np.uint8))
        for camera, mask in zip(run.scene.cameras, masks, strict=True):
            write_png(target.masks / Path(camera.name).with_suffix(".png"), mask)
        entries = [{**asdict(o), "gaussians": int((ids == o.id).sum()), "box": bounding_box(means[ids == o.id])}
                   for o in objects]
        target.objects_json.write_text(json.dumps(entries, indent=1))
        report = {"config": asdict(config), **stats, "objects": len(objects)}
        target.report.write_text(json.dumps(report, indent=1))
        write_png(target.sheet, segments_sheet(run.scene, masks, objects))
    emit("done", stage="segment", out=str(out.root), objects=len(objects))
    return report


def _test_psnr(layout: RunLayout) -> float | None:
    """The run's test PSNR from its metrics.json (None where it has no test views or no number), which tells a
    mostly faint model that fits its photos from one that does not (saliency_votes.weak_evidence)."""
    psnr = read_json(layout.metrics_json).get("psnr") if layout.metrics_json.is_file() else None
    return round(float(psnr), 2) if isinstance(psnr, (int, float)) and np.isfinite(psnr) else None


def _keep_previous(current: Path, previous: Path) -> None:
    """Copy the objects about to be replaced or extended to `previous`, atomically."""
    with atomic_output_dir(previous, replace=True) as tmp:
        shutil.copytree(current, tmp, dirs_exist_ok=True)


def restore_segments(layout: RunLayout) -> dict:
    """Swap RUN/segments with the objects the last `segment` replaced or extended (a second call swaps back)."""
    current, previous = layout.segments.root, layout.previous_segments.root
    if not SegmentsLayout(previous).objects_json.is_file():
        raise InputError(f"{layout.root} has no earlier objects to restore: no segment replaced or extended them")
    swap = current.parent / f".{current.name}.swap"
    shutil.rmtree(swap, ignore_errors=True)
    current.rename(swap)
    previous.rename(current)
    swap.rename(previous)
    objects = read_segment_objects(layout)
    emit("done", stage="segment", out=str(current), objects=len(objects), restored=True)
    return {"restored": True, "objects": len(objects)}


def _from_masks(run, means: np.ndarray, config: SegmentConfig, device: torch.device
                ) -> tuple[np.ndarray, dict, np.ndarray]:
    scene: Scene = run.scene
    views = scene.train
    folder = Path(config.from_masks)
    if not folder.is_dir():
        raise InputError(f"mask folder {folder} does not exist: give per-view PNGs named like the images")
    masks = [read_png(folder / Path(scene.cameras[i].name).with_suffix(".png"), "mask",
                      scene.cameras[i].size) for i in views]
    cameras = [scene.cameras[i] for i in views]
    depths = render_depths(run.gaussians, cameras, run.sh_degree, device, "segment: depth")
    return lift_masks(means, cameras, masks, depths, config.rel_tol, config.join)


def _salient_subject(run, ids: np.ndarray, opacity: np.ndarray, frame: Frame, supports: Supports,
                     config: SegmentConfig, stats: dict, device: torch.device) -> tuple[np.ndarray, int | None, dict]:
    """The proposals with the subject (engine.segment.saliency_votes) as an object of its own, its id, and why."""
    votes, _, colours, voxel = subject_evidence(run, frame, config, stats, device)
    means, solid = run.gaussians["means"].numpy(), opacity >= config.solid
    unsliced_supports = subject_supports(supports, means, solid, votes, frame, config)
    chosen, why = subject(votes, means, colours, solid, unsliced_supports.free, supports.near, frame.up, voxel,
                          config.min_vote, config.stack_gap, config.grow_vote,
                          subject_level(means, unsliced_supports, frame, config))
    why["walls_through_the_subject"] = len(supports.walls) - len(unsliced_supports.walls)
    if not chosen.any():
        return ids, None, why
    ids = ids.copy()
    first = int(ids.max()) + 1
    ids[chosen] = first
    return ids, first, why


def subject_supports(supports: Supports, means: np.ndarray, solid: np.ndarray, votes: np.ndarray, frame: Frame,
                     config: SegmentConfig) -> Supports:
    """The supports the subject stands free of: those found, less the walls that slice the salient Gaussians
    (engine.geometry.scene_geometry.unsliced: a thin figure is no wall)."""
    return unsliced(supports, means, solid, votes >= config.min_vote, config.plane_tol * frame.radius)


def subject_level(means: np.ndarray, supports: Supports, frame: Frame, config: SegmentConfig) -> np.ndarray:
    """(N,) bool: the level supports' bands, which the subject's growth never enters (saliency_votes.subject)."""
    return level_band(means, supports.planes, config.plane_tol * frame.radius)


def subject_evidence(run, frame: Frame, config: SegmentConfig, stats: dict, device: torch.device
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """What `subject` chooses from besides the supports: per Gaussian its salient vote, how many views saw it and
    its base colour, and the voxel (the proposals' `stats`, else the config's share of the orbit)."""
    scene: Scene = run.scene
    views = voting_views(scene.train)
    cameras = [scene.cameras[i] for i in views]
    depths = render_depths(run.gaussians, cameras, run.sh_degree, device, "segment: depth")
    votes, seen = salient_votes(run.gaussians["means"].numpy(), cameras, [scene.images[i] for i in views], depths,
                                SalientNet(config.salient_weights), config.rel_tol)
    colours = np.clip(run.gaussians["sh0"][:, 0].numpy() * SH_C0 + 0.5, 0, 1)
    return votes, seen, colours, stats.get("voxel") or config.voxel * frame.radius


def segments_sheet(scene: Scene, masks: list[np.ndarray], objects: list[SceneObject], views: int = 4
                   ) -> np.ndarray:
    """Four views around the scene: the image, and each object tinted and named where it shows."""
    rows = []
    for i in np.linspace(0, len(scene.cameras) - 1, min(views, len(scene.cameras))).astype(int):
        tinted = (0.45 * scene.images[i] + 0.55 * colorize_ids(masks[i])).astype(np.uint8)
        tinted = np.where(masks[i][..., None] > 0, tinted, scene.images[i] // 2)
        for o in objects:
            rows_, cols = np.nonzero(masks[i] == o.id)
            if len(rows_) > 20:
                at = (int(np.median(cols)), int(np.median(rows_)))
                cv2.putText(tinted, o.name, at, cv2.FONT_HERSHEY_SIMPLEX, max(tinted.shape[1] / 800, 0.3),
                            (255, 255, 255), 1, cv2.LINE_AA)
        rows.append(np.concatenate([label(scene.images[i], scene.names[i]), label(tinted, "objects")], axis=1))
    return np.concatenate(rows, axis=0)


def _add_selection(run, means: np.ndarray, config: SegmentConfig, device: torch.device
                   ) -> tuple[np.ndarray, list[SceneObject], dict]:
    """The segments so far with the selected Gaussians as one more object (they leave any other)."""
    if config.point:
        chosen = _clicked(run, means, config, device)
    else:
        chosen = inside_box(means, config.box) if config.box else _read_indices(Path(config.indices), len(means))
    ids, objects = np.zeros(len(means), np.int64), []
    if run.layout.segments.ids.is_file():
        ids, objects = np.load(run.layout.segments.ids).astype(np.int64), read_segment_objects(run.layout)
    new = max([o.id for o in objects], default=0) + 1
    if new > MAX_OBJECTS:
        raise InputError(f"{run.layout.segments.root} holds {len(objects)} objects, the most a run can: "
                         "delete it and select again")
    name = config.name or f"object_{new}"
    if name in {o.name for o in objects}:
        raise InputError(f"{run.layout.segments.objects_json} already has an object named {name!r}: "
                         "give another --name")
    ids[chosen] = new
    objects = [o for o in objects if (ids == o.id).any()] + [SceneObject(new, name, False)]
    return ids, objects, {"selected": int(chosen.sum())}


def _clicked(run, means: np.ndarray, config: SegmentConfig, device: torch.device) -> np.ndarray:
    """The object under a click: the rendered surface at pixel (U, V) of --view lifted to 3D, and the proposal
    (engine.segment.proposals: a piece off every support plane, its faint Gaussians joined) under it, with the
    pieces touching it there (`pieces_under`), and the proposal that renders at the pixel (`rendered_under`) with
    them. Why both, not the rendered one alone where it is not among them: either can be a sliver of the object
    that the other holds the rest of (a sliver alone renders at the click and on few other views). A pick that
    does not render at the click (`renders_at`: a click on the floor or a wall, or a piece behind a floater) is
    refused with one line, so the user clicks again."""
    scene: Scene = run.scene
    names = [c.name for c in scene.cameras]
    if len(config.point) != 2 or config.view not in names:
        raise InputError(f"--point takes U V and --view one of the run's images ({names[0]}, ...), not "
                         f"{config.point} in {config.view!r}")
    camera = scene.cameras[names.index(config.view)]
    u, v = config.point
    if not (0 <= u < camera.width and 0 <= v < camera.height):
        raise InputError(f"--point {u:g} {v:g} lies outside {config.view} ({camera.width}x{camera.height} px "
                         "in the run)")
    depth = render_depths(run.gaussians, [camera], run.sh_degree, device, "segment: depth")[0]
    z = float(depth[int(v), int(u)])
    if not np.isfinite(z) or z <= 0:
        raise InputError(f"nothing is rendered at --point {u:g} {v:g} of {config.view}: click on the object")
    target = backproject(camera, np.array(u), np.array(v), np.array(z))
    opacity = torch.sigmoid(run.gaussians["opacities"]).numpy()
    frame = camera_frame(scene.cameras)
    supports = clicked_supports(find_supports(means, opacity, frame, config), means, opacity, target, frame, config)
    ids, stats = propose(means, opacity, frame, supports, config)
    if not (ids > 0).any():
        raise InputError(f"{run.root} has no object off its support planes near --point: use --box")
    near = pieces_under(means, ids, target, 2 * stats["voxel"])
    seen = rendered_under(run.gaussians, run.sh_degree, ids, camera, (u, v), device)
    picked = np.union1d(near, [seen]) if seen else near
    chosen = np.isin(ids, picked)
    if not renders_at(run.gaussians, run.sh_degree, chosen, camera, (u, v), device):
        raise InputError(f"no object off the support planes renders at --point {u:g} {v:g} of {config.view} (the "
                         f"pieces under it there, proposals {picked.tolist()}, render elsewhere): click "
                         "nearer the object's middle or in another view, or use --box")
    return chosen


def clicked_supports(supports: Supports, means: np.ndarray, opacity: np.ndarray, target: np.ndarray, frame: Frame,
                     config: SegmentConfig) -> Supports:
    """The supports the clicked object stands free of: those found, less the walls whose solid Gaussians lie
    mostly within half an object's largest width (`max_width`) of the clicked point (unsliced: a tilted plane
    through the object is a slice of it, not a wall). Why: on a tiny CPU livingroom (training seed 7) a plane
    15 degrees off vertical through the plush, 78 solid Gaussians, 91% of them that near the click, was taken for
    a wall; the plush was then no proposal and the click took a 247-Gaussian piece inside it that covered none
    of it on the test views. A wall behind a mounted trophy reaches far past the trophy."""
    member = np.linalg.norm(means - target, axis=1) <= config.max_width / 2 * frame.radius
    return unsliced(supports, means, opacity >= config.solid, member, config.plane_tol * frame.radius)


def renders_at(gaussians: Gaussians, sh_degree: int, chosen: np.ndarray, camera: Camera,
               pixel: tuple[float, float], device: torch.device, reach_px: int = 2) -> bool:
    """Whether the `chosen` Gaussians dominate a pixel within `reach_px` of the click. Why: a pick the user
    cannot see where they clicked is a wrong pick (a floater's piece, a sliver behind the object), and saying so
    lets them click again, where a silent one would be removed in their stead."""
    mask = instance_masks(gaussians, chosen.astype(np.int64), [camera], sh_degree, device)[0]
    u, v = int(pixel[0]), int(pixel[1])
    return bool(mask[max(v - reach_px, 0):v + reach_px + 1, max(u - reach_px, 0):u + reach_px + 1].any())


def rendered_under(gaussians: Gaussians, sh_degree: int, ids: np.ndarray, camera: Camera,
                   pixel: tuple[float, float], device: torch.device, radius: float = 0.04) -> int:
    """The proposal whose Gaussians dominate the clicked pixel of `camera` (0: the supports or nothing). Why
    beside the lifted point: where the object's reconstruction splits into a body and a sliver that renders
    nothing, or a faint Gaussian sets the pixel's depth, the pieces near the lifted point can miss what the user
    saw there (a tiny CI training once took a sliver alone). The rendered identity takes only the proposals with
    Gaussians projected within `radius` of the image's width of the click, the most there first."""
    u, v = pixel
    pu, pv, z = project(camera, gaussians["means"].numpy())
    close = (z > 0) & (np.hypot(pu - u, pv - v) <= radius * camera.width) & (ids > 0)
    found, counts = np.unique(ids[close], return_counts=True)
    if not len(found):
        return 0
    kept = found[np.argsort(-counts, kind="stable")[:MAX_OBJECTS]]
    table = np.zeros(int(ids.max()) + 1, np.int64)
    table[kept] = np.arange(1, len(kept) + 1)
    label = int(instance_masks(gaussians, table[ids], [camera], sh_degree, device)[0][int(v), int(u)])
    return int(kept[label - 1]) if label else 0


def pieces_under(means: np.ndarray, ids: np.ndarray, target: np.ndarray, reach: float) -> np.ndarray:
    """The proposal ids (> 0) with a Gaussian within `reach` of the clicked surface point, else the nearest one.
    Why all of them: where a thin reconstruction splits one object into touching pieces (a plush of 209, 74 and
    35 Gaussians on one tiny CPU training), the piece nearest the click may be a sliver that renders nothing; the
    pieces that meet at the point clicked are the object under it."""
    pool = np.flatnonzero(ids > 0)
    distance = np.linalg.norm(means[pool] - target, axis=1)
    near = np.unique(ids[pool[distance <= reach]])
    return near if len(near) else ids[pool[[int(np.argmin(distance))]]]


def _read_indices(path: Path, count: int) -> np.ndarray:
    """(count,) bool from a .npy or whitespace-separated text file of Gaussian indices."""
    try:
        values = np.load(path) if path.suffix == ".npy" else np.loadtxt(path, dtype=np.int64, ndmin=1)
    except (OSError, ValueError) as exc:
        raise InputError(f"cannot read Gaussian indices from {path} ({exc}); give a .npy or a text file of "
                         "integers") from exc
    values = np.asarray(values).ravel()
    if values.dtype.kind not in "iu" or not len(values) or values.min() < 0 or values.max() >= count:
        raise InputError(f"{path} must hold Gaussian indices between 0 and {count - 1} (the run has {count})")
    chosen = np.zeros(count, bool)
    chosen[values] = True
    return chosen
