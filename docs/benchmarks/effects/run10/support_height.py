"""Why the 640x480 tabletop's trained hole masks miss (CPU, the generator's exact depth; tenth trainings).

1. The trained support plane (holes.json) against the surface under the object (the exact holes lifted by gt_depth/).
2. Our hole rule on exact depth and masks, with the background moved onto a plane parallel to that surface,
   d mm off it: how much of the IoU the plane's height alone decides.
3. `object_support` fed exact surfaces (points lifted from depth/ of every third training view, a tenth of the
   pixels) as stand-ins for the remaining Gaussians' centres: the height it picks.

    PYTHONPATH=. python support_height.py RECORDS SCENE_DIR...   (RECORDS: run10/records)
"""

import json
import sys
from pathlib import Path

import numpy as np

from engine.edit.holes import iou
from engine.edit.support_plane import object_support
from engine.formats.cameras import backproject, mean_up, pixel_grid
from engine.io.scene import load_scene
from engine.io.visibility import unseen_mask

records = Path(sys.argv[1])
for path in map(Path, sys.argv[2:]):
    scene, rng = load_scene(path, depth=True), np.random.default_rng(0)
    tid, up = scene.target.id, mean_up(np.stack([c.R for c in scene.cameras]))
    trained = json.loads((records / path.name / "holes.json").read_text())["support_plane"]
    tn, td = np.array(trained[:3]), trained[3]
    under = np.concatenate([backproject(scene.cameras[i], *[g[scene.holes[i]] for g in pixel_grid(scene.cameras[i])],
                                        scene.gt_depths[i][scene.holes[i]]) for i in sorted(scene.gt_depths)])
    height = float(np.median(under @ up))
    offset = float(np.median(under @ tn + td)) * 1000
    print(f"{path.name}: surface under the object {height:.4f}; {offset:+.2f} mm above the trained plane"
          f" ({np.degrees(np.arccos(min(1.0, abs(tn @ up)))):.2f} deg from the cameras' up)", flush=True)
    rest, obj = [], []
    for i in scene.train[::3]:
        cam, d, m = scene.cameras[i], scene.depths[i], scene.masks[i] == tid
        u, v = pixel_grid(cam)
        ok = np.isfinite(d) & (rng.random(d.shape) < 0.1)
        rest.append(backproject(cam, u[ok & ~m], v[ok & ~m], d[ok & ~m]))
        obj.append(backproject(cam, u[ok & m], v[ok & m], d[ok & m]))
    plane = object_support(np.concatenate(rest), np.concatenate(obj), up)
    print(f"  object_support on exact surfaces: {'none' if plane is None else f'{-plane[1]:.4f}'}", flush=True)
    train = [scene.cameras[j] for j in scene.train]
    depths = [scene.depths[j] for j in scene.train]
    occluders = [scene.masks[j] == tid for j in scene.train]
    for delta in (-4, -2, -1, 0, 1, 2, 4):
        values = []
        for i in sorted(scene.gt_depths)[:3]:
            cam, region = scene.cameras[i], scene.masks[i] == tid
            u, v = pixel_grid(cam)
            along = backproject(cam, u, v, np.ones(u.shape)) - cam.center  # z-depth 1 along each ray
            z = (height + delta / 1000 - cam.center @ up) / (along @ up)
            values.append(iou(unseen_mask(cam, region, np.where(region, z, np.nan), train, depths, 0.01, occluders),
                              scene.holes[i]))
        print(f"  plane {delta:+d} mm: hole IoU on three test views {np.round(values, 3).tolist()}", flush=True)
