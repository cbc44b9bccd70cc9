"""Stage 4 over a run: inpaint every view's hole in the removed scene's renders, RGB and depth.

Reads RUN/removed/{images,depth} and RUN/holes, writes RUN/inpainted/<inpainter>/{images,depth}, config.json
with timings and the prompt, and sheet_test.png / sheet_train.png (input, removed, hole, inpainted RGB and
depth per view) atomically. A view with an empty hole is copied through untouched. The masks are grown first,
by GROW_SHARE of the image's width unless --dilate gives the pixels: a render blurs a hole's edge into the pixel
or two beside it, and an inpainter fills from them (the paper dilates as well). The border that is wrong further
out (a remnant's edge, the contact shade relit in part) `holes` already took into the masks where the photos
contradict it (engine.edit.border); growing every hole by 4% of the width, as before, also replaced the right
border an inpainter reads (docs/BENCHMARKS.md, "Hole masks"). With --shield, what stands on the support within that
share of the width of the hole (another object, a remnant) is no source, since an inpainter runs its colour into
the fill; off by default, since on the eight tuning scenes it moved Ref-telea by -0.94 to +0.19 dB (mean -0.06). With
source "input" (the direct baseline, RUN/inpainted/direct-<inpainter>) the object's whole region is filled in the
input images instead, RGB only; an inpainter that takes no mask (nanobanana, the paper's Init-NanoBanana) always
works that way.
"""

from __future__ import annotations

import dataclasses
import json
import multiprocessing
import os
import threading
import time
from concurrent.futures import Executor, ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import torch

from engine.base.defaults import DEFAULT_INPAINTER
from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import Progress, emit
from engine.edit.holes import iou
from engine.edit.support_plane import removal_plane, standing_on, stop_at_plane
from engine.formats.cameras import Camera
from engine.formats.layout import HolesLayout, InpaintedLayout, RemovedLayout, RunLayout
from engine.inpaint.keep import like_ring
from engine.inpaint.registry import Inpainter, create
from engine.io.image_io import exr_name, read_depth, read_png, write_depth, write_png
from engine.io.masks import dilate, optional_mask
from engine.metrics.image_metrics import mean_and_worst
from engine.pictures.preview import colorize_depth, label, overlay
from engine.train.trained_run import load_run_scene

SHEET_ROWS = 6
PARENT_POLL_S = 1.0  # how often a worker process checks that its parent still runs
GROW_SHARE = 0.01  # the masks grow by this share of the image width by default (2 px at 160 px, 3 at 320)
SHIELD_TOL = 0.02  # of the plane's depth: nearer than the support by more than this, a pixel stands on it


def _saved_report(inpainted: InpaintedLayout) -> dict:
    """What an inpainting run wrote to its config.json: its settings under "config", and what it did."""
    return json.loads(inpainted.config_json.read_text())


def _saved_config(inpainted: InpaintedLayout) -> dict:
    """The settings an inpainting run wrote to its config.json."""
    return _saved_report(inpainted)["config"]


def inpainted_dilation(inpainted: InpaintedLayout) -> int:
    """The px an inpainting run grew its masks by (from its config.json): what it filled beyond the holes. Runs
    from before the growth's default wrote only the px they were given."""
    report = _saved_report(inpainted)
    return report.get("dilate_px", report["config"].get("dilate", 0))


def dilation_px(dilate: int, cameras: list[Camera]) -> int:
    """The px the masks grow by: `dilate` where it is given (0 or more), else GROW_SHARE of the views' median
    width (one number for the run: the completions read it back as one, inpainted_dilation)."""
    return dilate if dilate >= 0 else share_px(GROW_SHARE, cameras)


def share_px(share: float, cameras: list[Camera]) -> int:
    """`share` of the views' median width in pixels: one number for the run."""
    return round(share * float(np.median([c.width for c in cameras])))


def inpainted_holes(inpainted: InpaintedLayout) -> str:
    """The holes folder an inpainting run filled (from its config.json; "" where it named none)."""
    return _saved_config(inpainted).get("holes", "")


@dataclass
class InpaintConfig:
    run: str = ""  # the training run (its removed/ and holes/ are inpainted)
    inpainter: str = DEFAULT_INPAINTER  # a name from `engine plugins` (telea, fsr, exemplar, lama, ...)
    model: str = ""  # lama: .pt/.onnx (LAMA_MODEL); diffusion: diffusers folder (DIFFUSION_MODEL); nanobanana: name
    depth_range: str = "foreground"  # global | foreground (the paper's two depth representations)
    dilate: int = -1  # px added to the hole masks before inpainting; -1: 1% of the image's width (GROW_SHARE)
    prompt: str = ""  # default: the paper's (diffusion: generic; nanobanana: per scene family)
    source: str = "removed"  # removed: the holes of the removed renders; input: the object in the input images
    removed: str = ""  # default RUN/removed
    holes: str = ""  # default RUN/holes
    out: str = ""  # default RUN/inpainted/<inpainter>
    workers: int = 0  # views inpainted at once (0: the cores, up to 8, where the inpainter allows it; else 1)
    parallel: str = ""  # threads | processes: how views go at once ("": the inpainter's Inpainter.parallel_views)
    keep: float = 0.0  # keep the removed render where its colour is within this many ring deviations (0: fill all)
    shield: float = 0.0  # share of the image width: what stands on the support this near the hole is no source
    # (0.05 measured on the eight tuning scenes, H200 x2: Ref-telea -0.06 dB on the mean, so off)


def inpainted_inpainter(inpainted: InpaintedLayout):
    """The inpainter an inpainting run used, built as it was (its config.json): to fill more in its manner."""
    saved = _saved_config(inpainted)
    return _inpainter(InpaintConfig(**{f.name: saved[f.name] for f in dataclasses.fields(InpaintConfig)
                                       if f.name in saved}))


def _inpainter(config: InpaintConfig):
    options = {"depth_range": config.depth_range}
    if config.model:
        options["model"] = config.model
    return create(config.inpainter, **options)


def run_inpaint(config: InpaintConfig) -> dict:
    root = Path(config.run)
    run = RunLayout(root)
    removed = RemovedLayout(config.removed) if config.removed else run.removed
    holes = HolesLayout(config.holes) if config.holes else run.holes
    inpainter = _inpainter(config)
    direct = config.source == "input" or not inpainter.uses_mask
    if config.source not in ("removed", "input"):
        raise InputError(f"source {config.source!r} unknown: use 'removed' or 'input'")
    out = Path(config.out) if config.out else run.inpainted(config.inpainter, "input" if direct else "removed").root
    needed = [(removed.root, "remove")] if inpainter.uses_mask else []
    for folder, command in needed + ([] if direct else [(holes.root, "holes")]):
        if not folder.is_dir():
            raise InputError(f"{folder} missing: run `python -m engine {command} --run {root}` first")
    scene = load_run_scene(root)
    plane = None if direct else removal_plane(removed)
    prompt = config.prompt or inpainter.default_prompt(scene.root)
    sheets = _SheetRows(scene.test)
    workers, parallel = _workers(config, inpainter)
    start = time.perf_counter()
    grow = dilation_px(config.dilate, scene.cameras)
    with atomic_output_dir(out) as tmp_root:
        tmp = InpaintedLayout(tmp_root)
        job = _ViewJob(inpainter, grow, prompt, direct, plane, removed, holes, tmp, config.keep,
                       share_px(config.shield, scene.cameras))
        views = [(scene.images[i], scene.cameras[i]) for i in range(len(scene.cameras))]
        progress = Progress(f"inpaint {config.inpainter}", len(scene.cameras))
        for done, (i, row) in enumerate(_each_view(job, views, workers, parallel), start=1):
            sheets.add(i, row)
            progress.update(done)
        progress.close()
        seconds = time.perf_counter() - start
        for split, rows in sheets.rows().items():
            if rows:
                write_png(tmp.sheet_of(split), np.concatenate(rows, axis=0))
        report = {"config": dataclasses.asdict(config), "dilate_px": grow, "prompt": prompt,
                  "views": len(scene.cameras), "inpaint_seconds": round(seconds, 2), "workers": workers,
                  "parallel": parallel,
                  "hole_iou_as_inpainted": None if direct else inpainted_hole_iou(scene, holes, grow)}
        tmp.config_json.write_text(json.dumps(report, indent=1))
    emit("done", stage="inpaint", out=str(out), seconds=report["inpaint_seconds"])
    return report


def inpainted_hole_iou(scene, holes: HolesLayout, dilation: int) -> dict:
    """IoU against the scene's true holes (holes/, where it has them: every view of a generated scene rendered with
    --gt all, training views too) of the masks this stage filled, its own dilation included: what the inpainters
    and the completions that train on their fill were given, not what `holes` wrote."""
    scores = [iou(grown_hole(holes, scene.cameras[i].name, dilation), truth)
              for i, truth in sorted(scene.holes.items())]
    return mean_and_worst(scores)


def grown_hole(holes: HolesLayout, name: str, dilation: int) -> np.ndarray:
    """(H, W) bool: one view's hole as `holes` wrote it, grown by `dilation` px: the pixels this stage fills."""
    return dilate(read_png(holes.mask(name), kind="mask") > 0, dilation)


def _workers(config: InpaintConfig, inpainter) -> tuple[int, str]:
    """Views inpainted at once and how: --workers, else as many as there are cores (8 at most) where the
    inpainter allows it (Inpainter.parallel_views), else one; in the inpainter's threads or processes unless
    --parallel says which."""
    mode = config.parallel or inpainter.parallel_views()
    if mode not in ("", "threads", "processes"):
        raise InputError(f"parallel {config.parallel!r} unknown: use 'threads' or 'processes'")
    if config.workers > 0:
        workers = config.workers
    else:
        workers = min(os.cpu_count() or 1, 8) if mode else 1
    return workers, (mode or "threads") if workers > 1 else ""


@dataclass
class _ViewJob:
    """One view's inpainting with everything it needs held by value or by path, so that a worker process can
    run it from a pickled copy (the inpainter too: those that ask for processes hold no weights)."""

    inpainter: Inpainter
    dilate: int
    prompt: str | None
    direct: bool
    plane: tuple[np.ndarray, float] | None
    removed: RemovedLayout
    holes: HolesLayout
    out: InpaintedLayout
    keep: float = 0.0
    shield: int = 0

    def __call__(self, image: np.ndarray, camera: Camera) -> np.ndarray | None:
        """Fill one view and write it under `out`; its contact sheet row, or None if it has no hole."""
        if not self.direct:
            return _fill_hole(self.inpainter, self.dilate, self.prompt, image, camera, self.plane, self.removed,
                              self.holes, self.out, self.keep, self.shield)
        # the direct baseline: the object painted out of the input image (its region), RGB only
        uses_mask = self.inpainter.uses_mask
        region = dilate(_direct_region(self.removed, camera.name), self.dilate) if uses_mask else None
        filled = self.inpainter.inpaint(image, region, "rgb", self.prompt)
        write_png(self.out.images / camera.name, filled)
        return np.concatenate([label(image, f"{camera.name} input"), label(filled, "inpainted")], 1)


def _each_view(job: _ViewJob, views: list[tuple[np.ndarray, Camera]], workers: int, parallel: str):
    """(view index, its sheet row) for every view, in the order they finish: one after the other, or `workers`
    threads or processes at once. Threads keep torch to one thread each meanwhile (a view's small ops cannot
    use more, and threads of threads only contend); processes are spawned (CUDA cannot be forked) and do the
    same in themselves. A failing view stops the rest and its error propagates."""
    if workers <= 1:
        yield from ((i, job(*view)) for i, view in enumerate(views))
        return
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        with _pool(workers, parallel) as pool:
            futures = {pool.submit(job, *view): i for i, view in enumerate(views)}
            try:
                for future in as_completed(futures):
                    yield futures[future], future.result()
            finally:  # an error or a cancel: start no more views
                for future in futures:
                    future.cancel()
    finally:
        torch.set_num_threads(threads)


def _pool(workers: int, parallel: str) -> Executor:
    if parallel == "processes":
        return ProcessPoolExecutor(workers, multiprocessing.get_context("spawn"), initializer=_start_worker,
                                   initargs=(os.getpid(),))
    return ThreadPoolExecutor(workers)


def _start_worker(parent: int) -> None:
    """A worker process inpaints one view at a time: torch keeps to one thread, as in the threads' way, and
    OpenCV too (the threads share their process's OpenCV pool; a process has its own). It ends
    when its parent does: a parent killed outright (Ray cancelling a task, `kill -9`) leaves its pool's workers
    waiting for work forever, each holding a GPU context."""
    torch.set_num_threads(1)
    cv2.setNumThreads(1)
    threading.Thread(target=_end_with, args=(parent,), daemon=True).start()


def _end_with(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(PARENT_POLL_S)
    os._exit(1)


class _SheetRows:
    """The contact sheets' rows: the first SHEET_ROWS views with a hole of each split, in view order, kept
    while views finish in any order (only those that can still make the sheet are held)."""

    def __init__(self, test: list[int]) -> None:
        self.test, self.held = set(test), {"test": {}, "train": {}}

    def add(self, i: int, row: np.ndarray | None) -> None:
        if row is None:
            return
        held = self.held["test" if i in self.test else "train"]
        held[i] = row
        for extra in sorted(held)[SHEET_ROWS:]:
            del held[extra]

    def rows(self) -> dict[str, list[np.ndarray]]:
        return {split: [held[i] for i in sorted(held)] for split, held in self.held.items()}


def _direct_region(removed: RemovedLayout, name: str) -> np.ndarray:
    """What the direct baseline paints over in an input image: the object's region, and its shadow where
    `remove` relit one (removed/effects: the input images still show it; the other methods relit it in 3D)."""
    region = read_png(removed.masks / name, kind="mask") > 0
    return region | optional_mask(removed.effects.mask(name), region.shape[::-1])


def _fill_hole(inpainter, dilation: int, prompt: str | None, image: np.ndarray, camera: Camera,
               plane: tuple[np.ndarray, float] | None, removed: RemovedLayout, holes: HolesLayout,
               out: InpaintedLayout, keep: float = 0.0, shield: int = 0) -> np.ndarray | None:
    """Inpaint one view's hole in the removed render, RGB and depth; its sheet row, or None if no hole.
    With `keep` above 0 the render stays (colour and depth) where it already looks like the hole's surroundings
    (engine.inpaint.keep); the sheet's hole shows what was filled.

    The depth fill stops at the support plane `remove` found: an inpainter fills depth from the hole's
    border, which takes in the floor or backdrop seen past the table's edge (statue: median 9% and up to
    2.2x deeper than the slab top), and FT's new Gaussians and Ref's carried fill are placed by it.

    With `shield` (px) what stands on that plane within it of the hole (another object beside the removed one, a
    remnant on its edge: engine.edit.support_plane.standing_on) is filled with the hole and then put back, so the
    inpainter reads the hole's colours from the support alone: an inpainter fills from the hole's border, and an
    orange beside the removed object ran into the livingroom_s100 fill as orange streaks (2f7158c)."""
    name = camera.name
    rgb = read_png(removed.images / name)
    depth = read_depth(removed.depth / exr_name(name))
    hole = grown_hole(holes, name, dilation)
    shielded = _shielded(camera, hole, depth, plane, shield)
    filled = inpainter.inpaint(rgb, hole | shielded, "rgb", prompt)
    filled_depth = inpainter.inpaint(depth, hole | shielded, "depth", prompt)
    filled[shielded], filled_depth[shielded] = rgb[shielded], depth[shielded]
    if plane is not None and hole.any():
        filled_depth = stop_at_plane(camera, hole, filled_depth, plane, 0.0)
    kept = like_ring(rgb, hole, keep) & np.isfinite(depth)
    if kept.any():
        filled, filled_depth = np.where(kept[..., None], rgb, filled), np.where(kept, depth, filled_depth)
    write_png(out.images / name, filled)
    write_depth(out.depth / exr_name(name), filled_depth)
    return _sheet_row(image, rgb, hole & ~kept, filled, filled_depth, name) if hole.any() else None


def _shielded(camera: Camera, hole: np.ndarray, depth: np.ndarray, plane: tuple[np.ndarray, float] | None,
              px: int) -> np.ndarray:
    """The pixels within `px` of the hole, outside it, that stand on the support plane (none without a plane)."""
    if px <= 0 or plane is None or not hole.any():
        return np.zeros_like(hole)
    return standing_on(camera, dilate(hole, px) & ~hole, depth, plane, SHIELD_TOL)


def _sheet_row(image, removed, hole, filled, filled_depth, name) -> np.ndarray:
    return np.concatenate([label(image, f"{name} input"), label(removed, "removed"),
                           label(overlay(removed, hole), "hole"), label(filled, "inpainted"),
                           label(colorize_depth(filled_depth), "inpainted depth")], axis=1)
