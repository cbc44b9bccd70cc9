"""Hole masks from a dumped run (original train depths, removed depths), their errors against the truth."""

import json
import sys
from pathlib import Path

import cv2
import numpy as np

from engine.edit.holes import _object_depth, iou
from engine.edit.support_plane import stop_at_plane
from engine.io.scene import load_scene
from engine.io.visibility import unseen_mask

name, scene_dir = sys.argv[1], sys.argv[2]
variant = sys.argv[3] if len(sys.argv) > 3 else "base"
d = np.load(f"/tmp/s4/d/{name}_depth.npz")
rem = json.load(open(f"/tmp/s4/d/{name}_removal.json"))
plane = (np.array(rem["support_plane"][:3]), rem["support_plane"][3])
scene = load_scene(Path(scene_dir))
tid = scene.target.id
train = list(d["train"])
orig = [x.astype(np.float32) for x in d["orig"]]
after = [x.astype(np.float32) for x in d["after"]]
cams = [scene.cameras[i] for i in train]
regions = [scene.masks[i] == tid for i in range(len(scene.cameras))]
occ = [regions[i] for i in train]
ERODE = int(sys.argv[4]) if len(sys.argv) > 4 else 0

occ_test = [cv2.erode(o.astype(np.uint8), np.ones((2 * ERODE + 1,) * 2, np.uint8)) > 0 for o in occ] if ERODE else occ
near = _object_depth(orig, occ)


def farthest(depth, k):
    x = np.where(np.isfinite(depth), depth, 1e6).astype(np.float32)
    m = cv2.dilate(x, np.ones((k, k), np.uint8))
    return np.where(m >= 1e6, np.inf, m)


if variant.startswith("max"):
    k = int(variant[3:])
    from engine.io.visibility import farthest_nearby

    orig = [farthest_nearby(o, k // 2) for o in orig]
if variant.startswith("omax"):
    k = int(variant[4:])
    orig = [np.where(r, o, farthest(np.where(r, 0, o), k)) for o, r in zip(orig, occ, strict=False)]

rows, ious = [], []
for i in sorted(scene.holes):
    cam = scene.cameras[i]
    bg = stop_at_plane(cam, regions[i], after[i], plane, 0.01)
    h = unseen_mask(cam, regions[i], bg, cams, orig, 0.01, occ_test, near) | (regions[i] & ~np.isfinite(bg))
    t = scene.holes[i]
    ious.append(iou(h, t))
    img = scene.images[i].copy()
    img[h & t] = (0, 255, 0)
    img[h & ~t] = (255, 0, 0)
    img[~h & t] = (0, 0, 255)
    ys, xs = np.nonzero(regions[i])
    y0, y1, x0, x1 = ys.min() - 8, ys.max() + 8, xs.min() - 8, xs.max() + 8
    rows.append(cv2.resize(img[y0:y1, x0:x1], None, fx=4, fy=4, interpolation=cv2.INTER_NEAREST))
print(name, variant, f"IoU {np.mean(ious):.3f}", np.round(ious, 2))
w = max(r.shape[1] for r in rows)
hh = max(r.shape[0] for r in rows)
rows = [np.pad(r, ((0, hh - r.shape[0]), (0, w - r.shape[1]), (0, 0))) for r in rows]
cv2.imwrite(f"/tmp/s4/{name}_holeerr.png", cv2.cvtColor(np.concatenate(rows[:3], 1), cv2.COLOR_RGB2BGR))
