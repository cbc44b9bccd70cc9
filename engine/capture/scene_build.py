"""Turn the Blender generator's raw renders into a scene folder with exact ground truth.

scripts/make_scene.py (Blender's Python) renders multi-part EXRs (linear colour, z-depth, object index)
and writes cameras.json; this module (the engine's Python, which has OpenImageIO and pycolmap) writes
images/, gt/, masks/, depth/, gt_depth/, holes/, effects/, sparse/0/ and split.json. See engine.capture.scene for the
layout.
"""

from __future__ import annotations

import dataclasses
import json
import shutil
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import Progress, emit
from engine.formats.cameras import Camera, backproject, pixel_grid, project, read_cameras_json
from engine.formats.layout import RendersLayout, SceneLayout
from engine.io.colmap_model import ColmapModel, write_model
from engine.io.image_io import linear_to_srgb8, read_exr_channels, write_depth, write_png
from engine.io.masks import dilate
from engine.io.visibility import exact_tolerance, seen_by_any, unseen_mask, unseen_view_pixels

BACKGROUND_DEPTH = 1e9  # Cycles writes 1e10 where a ray hits nothing; stored as inf
EFFECT_DIFF = 12  # of 255: a change this large is the object's doing, not Cycles' noise between two renders


@dataclass(frozen=True)
class BuildConfig:
    """Settings for turning renders into a scene folder."""

    max_points: int = 30_000  # sparse points written to the COLMAP model
    max_track: int = 4  # observations kept per point
    rel_tol: float | None = None  # depth tolerance of the ground-truth hole test (None: exact_tolerance)
    seed: int = 0


@dataclass
class RenderPass:
    """The three passes of one render."""

    rgb: np.ndarray  # (H, W, 3) uint8 sRGB
    depth: np.ndarray  # (H, W) float32, inf where nothing was hit
    ids: np.ndarray  # (H, W) uint8 object index


def read_render(path: Path) -> RenderPass:
    """Read one of Blender's multi-part EXRs (channel names differ between Blender 4.x and 5.x)."""
    channels = read_exr_channels(path)

    def find(*suffixes: str) -> np.ndarray:
        for name, data in channels.items():
            if any(name.endswith(s) for s in suffixes):
                return data
        raise InputError(f"render {path} lacks a {suffixes[0]} channel; enable that pass and re-render")

    rgb = np.stack([find("Combined.R"), find("Combined.G"), find("Combined.B")], axis=-1)
    depth = find("Depth.Z", ".Z")
    depth = np.where(depth >= BACKGROUND_DEPTH, np.inf, depth).astype(np.float32)
    ids = np.rint(find("Object Index.X", "IndexOB.X")).clip(0, 255).astype(np.uint8)
    return RenderPass(linear_to_srgb8(rgb), depth, ids)


def build_scene(renders: Path, out: Path, config: BuildConfig = BuildConfig()) -> Path:
    """Write a complete scene folder at `out` from the renders in `renders`; returns `out`."""
    source = RendersLayout(renders)
    cameras = read_cameras_json(source.cameras_json)
    split = json.loads(source.split_json.read_text())
    objects = json.loads(source.objects_json.read_text())
    target_id = next(o["id"] for o in objects if o["target"])
    if config.rel_tol is None:
        config = dataclasses.replace(config, rel_tol=exact_tolerance(cameras))
    train = [i for i, c in enumerate(cameras) if c.name in set(split["train"])]
    with atomic_output_dir(out) as tmp_root:
        tmp = SceneLayout(tmp_root)
        for sub in (tmp.images, tmp.masks, tmp.depth, tmp.gt, tmp.gt_depth, tmp.holes, tmp.effects, tmp.unseen):
            sub.mkdir()
        views = _write_views(source.with_object, cameras, tmp.images, tmp.depth, tmp.masks)
        gt_names = sorted(p.stem for p in source.without_object.glob("*.exr"))
        gt_index = [i for i, c in enumerate(cameras) if Path(c.name).stem in gt_names]
        gt_views = _write_views(source.without_object, [cameras[i] for i in gt_index], tmp.gt, tmp.gt_depth)
        progress = Progress("holes", len(gt_index))
        for k, (i, gt) in enumerate(zip(gt_index, gt_views, strict=True)):
            hole = unseen_mask(cameras[i], views[i].ids == target_id, gt.depth,
                               [cameras[j] for j in train], [views[j].depth for j in train], config.rel_tol)
            write_png(tmp.holes / cameras[i].name, (hole * 255).astype(np.uint8))
            effect = effect_region(views[i].rgb, gt.rgb, views[i].ids == target_id)
            write_png(tmp.effects / cameras[i].name, (effect * 255).astype(np.uint8))
            progress.update(k + 1)
        progress.close()
        write_unseen_views(cameras, [v.depth for v in views], train, split["test"], tmp.unseen, config.rel_tol)
        model = sample_points(cameras, views, train, config)
        write_model(tmp.sparse / "0", model)
        tmp.objects_json.write_text(json.dumps(objects, indent=1))
        tmp.split_json.write_text(json.dumps(split, indent=1))
        shutil.copy(source.meta_json, tmp.scene_json)
    emit("done", out=str(out))
    return out


def write_unseen_views(cameras: list[Camera], depths: list[np.ndarray], train: list[int], test: list[str],
                       out: Path, rel_tol: float) -> None:
    """unseen/: per test view, the pixels no training view saw (engine.io.visibility.unseen_view_pixels)."""
    seen_by, names = ([cameras[j] for j in train], [depths[j] for j in train]), set(test)
    for i, camera in enumerate(cameras):
        if camera.name in names:
            unseen = unseen_view_pixels(camera, depths[i], *seen_by, rel_tol)
            write_png(out / camera.name, (unseen * 255).astype(np.uint8))


def effect_region(image: np.ndarray, gt: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(H, W) bool: what the target did to the rest of the view (its shadow, its reflection, light it
    bounced): pixels outside its mask (grown by one pixel, its antialiased edge) where the render with it
    and the one without differ by more than EFFECT_DIFF in some channel, with specks thinner than 3 px
    (noise) opened away."""
    changed = (np.abs(image.astype(np.int16) - gt.astype(np.int16)).max(-1) > EFFECT_DIFF) & ~dilate(target, 1)
    return cv2.morphologyEx(changed.astype(np.uint8), cv2.MORPH_OPEN, np.ones((3, 3), np.uint8)) > 0


def _write_views(folder: Path, cameras: list[Camera], image_dir: Path, depth_dir: Path,
                 mask_dir: Path | None = None) -> list[RenderPass]:
    """Convert each camera's render; returns the passes (colour dropped) for later steps."""
    progress = Progress(image_dir.name, len(cameras))
    passes = []
    for k, camera in enumerate(cameras):
        render = read_render(folder / f"{Path(camera.name).stem}.exr")
        if render.depth.shape != (camera.height, camera.width):
            raise InputError(f"render {folder / camera.name} does not match its camera size; re-render")
        write_png(image_dir / camera.name, render.rgb)
        write_depth(depth_dir / f"{Path(camera.name).stem}.exr", render.depth)
        if mask_dir is not None:
            write_png(mask_dir / camera.name, render.ids)
        passes.append(render)
        progress.update(k + 1)
    progress.close()
    return passes


def sample_points(cameras: list[Camera], views: list[RenderPass], train: list[int],
                  config: BuildConfig) -> ColmapModel:
    """Sparse points on surfaces the training views see, coloured from the images, with short tracks."""
    rng = np.random.default_rng(config.seed)
    per_view = max(1, config.max_points // len(train))
    points, colors, sources = [], [], []
    for i in train:
        u, v = pixel_grid(cameras[i])
        valid = np.flatnonzero(np.isfinite(views[i].depth).ravel())
        pick = rng.choice(valid, size=min(per_view, valid.size), replace=False)
        points.append(backproject(cameras[i], u.ravel()[pick], v.ravel()[pick], views[i].depth.ravel()[pick]))
        colors.append(views[i].rgb.reshape(-1, 3)[pick])
        sources.append(np.full(pick.size, i))
    xyz, rgb, source = np.concatenate(points), np.concatenate(colors), np.concatenate(sources)
    observations: list[list[tuple[int, float, float]]] = [[] for _ in range(len(xyz))]
    for i in train:
        u, v, z = project(cameras[i], xyz)
        seen = seen_by_any(xyz, [cameras[i]], [views[i].depth], config.rel_tol)
        for p in np.flatnonzero(seen | (source == i)):
            if len(observations[p]) < config.max_track or source[p] == i:
                observations[p].append((i, float(u[p]), float(v[p])))
    return ColmapModel(cameras=cameras, points=xyz, colors=rgb, observations=observations)
