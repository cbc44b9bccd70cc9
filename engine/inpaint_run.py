"""Stage 4 over a run: inpaint every view's hole in the removed scene's renders, RGB and depth.

Reads RUN/removed/{images,depth} and RUN/holes, writes RUN/inpainted/<inpainter>/{images,depth}, config.json
with timings, and sheet_test.png / sheet_train.png (input, removed, hole, inpainted RGB and depth per view)
atomically. A view with an empty hole is copied through untouched. The mask can be dilated first: LaMa
fills larger masks better (the paper dilates).
"""

from __future__ import annotations

import dataclasses
import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from engine.errors import InputError
from engine.image_io import exr_name, read_depth, read_png, write_depth, write_png
from engine.inpainters import create
from engine.masks import dilate
from engine.output_dir import atomic_output_dir
from engine.preview import colorize_depth, label, overlay
from engine.progress import Progress, emit
from engine.scene import load_scene

SHEET_ROWS = 6


@dataclass
class InpaintConfig:
    run: str = ""
    inpainter: str = "fsr"
    model: str = ""  # weights for inpainters that need them (lama: .pt or .onnx; or LAMA_MODEL)
    depth_range: str = "foreground"  # global | foreground (the paper's two depth representations)
    dilate: int = 0  # px added to the hole masks before inpainting
    prompt: str = ""
    removed: str = ""  # default RUN/removed
    holes: str = ""  # default RUN/holes
    out: str = ""  # default RUN/inpainted/<inpainter>


def _inpainter(config: InpaintConfig):
    options = {"depth_range": config.depth_range}
    if config.model:
        options["model"] = config.model
    return create(config.inpainter, **options)


def run_inpaint(config: InpaintConfig) -> dict:
    root = Path(config.run)
    removed = Path(config.removed) if config.removed else root / "removed"
    holes = Path(config.holes) if config.holes else root / "holes"
    out = Path(config.out) if config.out else root / "inpainted" / config.inpainter
    for folder, command in ((removed, "remove"), (holes, "holes")):
        if not folder.is_dir():
            raise InputError(f"{folder} missing: run `python -m engine {command} --run {root}` first")
    inpainter = _inpainter(config)
    scene = load_scene(json.loads((root / "config.json").read_text())["scene"])
    sheets: dict[str, list[np.ndarray]] = {"test": [], "train": []}
    seconds = 0.0
    with atomic_output_dir(out) as tmp:
        progress = Progress(f"inpaint {config.inpainter}", len(scene.cameras))
        for i, camera in enumerate(scene.cameras):
            rgb = read_png(removed / "images" / camera.name)
            depth = read_depth(removed / "depth" / exr_name(camera.name))
            hole = dilate(read_png(holes / camera.name, kind="mask") > 0, config.dilate)
            start = time.perf_counter()
            filled = inpainter.inpaint(rgb, hole, "rgb", config.prompt or None)
            filled_depth = inpainter.inpaint(depth, hole, "depth", config.prompt or None)
            seconds += time.perf_counter() - start
            write_png(tmp / "images" / camera.name, filled)
            write_depth(tmp / "depth" / exr_name(camera.name), filled_depth)
            split = "test" if i in scene.test else "train"
            if hole.any() and len(sheets[split]) < SHEET_ROWS:
                sheets[split].append(_sheet_row(scene.images[i], rgb, hole, filled, filled_depth, camera.name))
            progress.update(i + 1)
        progress.close()
        for split, rows in sheets.items():
            if rows:
                write_png(tmp / f"sheet_{split}.png", np.concatenate(rows, axis=0))
        report = {"config": dataclasses.asdict(config), "views": len(scene.cameras),
                  "inpaint_seconds": round(seconds, 2)}
        (tmp / "config.json").write_text(json.dumps(report, indent=1))
    emit("done", stage="inpaint", out=str(out), seconds=report["inpaint_seconds"])
    return report


def _sheet_row(image, removed, hole, filled, filled_depth, name) -> np.ndarray:
    return np.concatenate([label(image, f"{name} input"), label(removed, "removed"),
                           label(overlay(removed, hole), "hole"), label(filled, "inpainted"),
                           label(colorize_depth(filled_depth), "inpainted depth")], axis=1)
