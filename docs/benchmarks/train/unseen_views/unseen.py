"""Issue 17's worst test view: how much of each test view no training view saw, from the generator's exact depth,
and (given a run's test renders) each view's PSNR over all pixels and over those some training view saw.

The masks are engine.io.visibility.unseen_view_pixels, which the scene generator now writes as unseen/ and the
evaluation reads (metrics.json: psnr_seen_per_view, worst_view_gap_seen). `--write` adds unseen/ to a scene
generated before that (it has depth/), so the benchmark's packed scenes carry it.

    python3 unseen.py SCENE [RENDERS] [--write]
"""

from __future__ import annotations

import sys
from pathlib import Path

import cv2
import numpy as np

from engine.formats.layout import SceneLayout
from engine.io.scene import load_scene
from engine.io.scene_build import write_unseen_views
from engine.io.visibility import exact_tolerance, unseen_view_pixels


def main(scene_dir: Path, renders: Path | None, write: bool) -> None:
    scene = load_scene(scene_dir, depth=True)
    train = [scene.cameras[i] for i in scene.train]
    depths = [scene.depths[i] for i in scene.train]
    tol = exact_tolerance(scene.cameras)
    if write:
        out = SceneLayout(scene_dir).unseen
        if out.exists():
            raise SystemExit(f"{out} exists already")
        out.mkdir()
        write_unseen_views(scene.cameras, scene.depths, scene.train, [scene.names[i] for i in scene.test], out, tol)
    rows = []
    for i in scene.test:
        camera = scene.cameras[i]
        unseen = unseen_view_pixels(camera, scene.depths[i], train, depths, tol)
        row = {"view": camera.name, "unseen_share": float(unseen.mean())}
        if renders is not None:
            render = cv2.imread(str(renders / camera.name))[..., ::-1].astype(np.float64)
            err = ((render - scene.images[i].astype(np.float64)) ** 2).mean(-1)
            row |= {"psnr": 10 * np.log10(255 ** 2 / err.mean()),
                    "psnr_seen": 10 * np.log10(255 ** 2 / err[~unseen].mean()),
                    "unseen_error_share": err[unseen].sum() / err.sum()}
        rows.append(row)
    for row in rows:
        print("  ".join(f"{k} {v:.4f}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()))
    if renders is not None:
        for key in ("psnr", "psnr_seen"):
            values = [r[key] for r in rows]
            print(f"{key}: mean {np.mean(values):.2f}, worst view {np.mean(values) - min(values):.2f} dB below it")


if __name__ == "__main__":
    flags = [a for a in sys.argv[1:] if a.startswith("--")]
    paths = [Path(a) for a in sys.argv[1:] if not a.startswith("--")]
    main(paths[0], paths[1] if len(paths) > 1 else None, "--write" in flags)
