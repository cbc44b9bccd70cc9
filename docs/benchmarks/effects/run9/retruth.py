"""Rewrite a generated scene's holes/ with today's truth (CPU, the generator's exact depth).

The 640x480 scenes of the eighth trainings were generated when the exact holes allowed 1% of depth; the
generator now allows `exact_tolerance` (2/focal, 0.32% at 640 px). Rendering them again takes 12-20 min each on
2 cores and gives the same images, so this recomputes only holes/ from the scene's own depth/ and gt_depth/,
the same test as `engine.io.scene_build.build_scene`, and swaps the folder in whole (the old one kept as
holes_1pct/).

    python retruth.py SCENE...
"""

import shutil
import sys
from pathlib import Path

import numpy as np

from engine.formats.layout import SceneLayout
from engine.io.image_io import write_png
from engine.io.scene import load_scene
from engine.io.visibility import exact_tolerance, unseen_mask

for path in map(Path, sys.argv[1:]):
    scene, layout = load_scene(path, depth=True), SceneLayout(path)
    tol = exact_tolerance(scene.cameras)
    train = [scene.cameras[j] for j in scene.train]
    depths = [scene.depths[j] for j in scene.train]
    new = path / "holes.new"
    shutil.rmtree(new, ignore_errors=True)
    new.mkdir()
    shares = []
    for i in sorted(scene.gt_depths):
        region = scene.masks[i] == scene.target.id
        hole = unseen_mask(scene.cameras[i], region, scene.gt_depths[i], train, depths, tol)
        write_png(new / scene.cameras[i].name, (hole * 255).astype(np.uint8))
        shares.append(hole.sum() / max(1, region.sum()))
    if not (path / "holes_1pct").exists():
        layout.holes.rename(path / "holes_1pct")
    else:
        shutil.rmtree(layout.holes)
    new.rename(layout.holes)
    print(f"{path.name}: truth at {tol:.3%} covers {np.mean(shares):.3f} of the object's pixels", flush=True)
