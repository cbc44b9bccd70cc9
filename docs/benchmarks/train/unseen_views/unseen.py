"""Issue 17's worst test view: how much of each test view no training view saw, from the generator's exact depth,
and (given a run's test renders) each view's PSNR over the pixels some training view saw.

A surface point is seen when a training view has it in frame, in front, and not behind its own surface there
(engine.io.visibility.seen_by_any at the scene's exact tolerance). Sky (infinite depth) is a direction: seen when a
training view has that direction in frame and shows sky there too. What no training view saw, no training can
know; a test view that shows much of it falls below the others whatever the training does.

    python3 unseen.py SCENE [RENDERS]
"""

from __future__ import annotations

import sys
from pathlib import Path

import cv2
import numpy as np

from engine.formats.cameras import Camera, backproject, pixel_grid, project, sample_nearest
from engine.io.scene import load_scene
from engine.io.visibility import exact_tolerance, seen_by_any

FAR = 1e4  # a sky pixel's point along its ray: far enough that only its direction counts


def seen_pixels(camera: Camera, depth: np.ndarray, train: list[Camera], depths: list[np.ndarray],
                tol: float) -> np.ndarray:
    """(H, W) bool: the test view's pixels some training view saw."""
    u, v = pixel_grid(camera)
    sky = ~np.isfinite(depth)
    seen = np.zeros(depth.shape, bool)
    surface = backproject(camera, u[~sky], v[~sky], depth[~sky])
    seen[~sky] = seen_by_any(surface, train, depths, tol)
    ahead = backproject(camera, u[sky], v[sky], np.full(int(sky.sum()), FAR)) - camera.center
    sky_seen = np.zeros(len(ahead), bool)
    for other, other_depth in zip(train, depths, strict=True):
        pu, pv, z = project(other, other.center + ahead)
        shown, inside = sample_nearest(other_depth, pu, pv)
        sky_seen |= inside & (z > 0) & ~np.isfinite(shown)
    seen[sky] = sky_seen
    return seen


def main(scene_dir: Path, renders: Path | None) -> None:
    scene = load_scene(scene_dir, depth=True)
    depth_of = scene.depths
    train = [scene.cameras[i] for i in scene.train]
    depths = [depth_of[i] for i in scene.train]
    tol = exact_tolerance(scene.cameras)
    rows = []
    for i in scene.test:
        camera = scene.cameras[i]
        seen = seen_pixels(camera, depth_of[i], train, depths, tol)
        row = {"view": camera.name, "unseen_share": 1 - seen.mean()}
        if renders is not None:
            render = cv2.imread(str(renders / camera.name))[..., ::-1].astype(np.float64)
            err = ((render - scene.images[i].astype(np.float64)) ** 2).mean(-1)
            row |= {"psnr": 10 * np.log10(255 ** 2 / err.mean()),
                    "psnr_seen": 10 * np.log10(255 ** 2 / err[seen].mean()),
                    "unseen_error_share": err[~seen].sum() / err.sum()}
        rows.append(row)
    for row in rows:
        print("  ".join(f"{k} {v:.4f}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()))
    if renders is not None:
        for key in ("psnr", "psnr_seen"):
            values = [r[key] for r in rows]
            print(f"{key}: mean {np.mean(values):.2f}, worst view {np.mean(values) - min(values):.2f} dB below it")


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]) if len(sys.argv) > 2 else None)
