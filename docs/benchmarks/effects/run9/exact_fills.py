"""What the 2D carry studies share (carry_compare.py, carry_eval.py, run12/consensus_eval.py): each test view of a
generated scene with its exact hole (holes/) inpainted in gt/ and gt_depth/ by one inpainter, and scores in a
hole against gt/ (the benchmark's m-PSNR and m-SSIM)."""

from pathlib import Path

import numpy as np
import torch

from engine.complete.reference_fill import ViewFill
from engine.io.image_io import read_png
from engine.io.scene import load_scene
from engine.metrics.image_metrics import psnr_from_mse, ssim_map


def hole_scores(image: np.ndarray, truth: np.ndarray, hole: np.ndarray) -> tuple[float, float]:
    a, b = (torch.from_numpy(x.astype(np.float32) / 255) for x in (image, truth))
    return psnr_from_mse(((a - b) ** 2).mean(-1)[hole].mean().item()), ssim_map(a, b)[hole].mean().item()


def own_fills(inpainter, path: Path) -> tuple[dict[int, ViewFill], dict[int, np.ndarray]]:
    """Per test view with a hole of at least 50 px: its own fill, and its gt/ image."""
    scene, fills, truths = load_scene(path, depth=True), {}, {}
    for i in sorted(scene.gt_depths):
        camera = scene.cameras[i]
        hole = read_png(path / "holes" / camera.name, "mask", camera.size) > 0
        if hole.sum() >= 50:
            truths[i] = scene.gt_images[i]
            fills[i] = ViewFill(camera, hole, inpainter.inpaint(truths[i], hole, "rgb"),
                                inpainter.inpaint(scene.gt_depths[i].astype(np.float32), hole, "depth"))
    return fills, truths
