"""Our hole rule fed exact depths: how much of the tabletop's extra hole comes from the mask rule itself."""

import sys
from pathlib import Path

import cv2
import numpy as np

from engine.edit.holes import iou
from engine.io.masks import dilate
from engine.io.scene import load_scene
from engine.io.visibility import unseen_mask

scene = load_scene(Path(sys.argv[1]), depth=True)
tid = scene.target.id if hasattr(scene.target, "id") else scene.target
train = [scene.cameras[j] for j in scene.train]
regions = [scene.masks[i] == tid for i in range(len(scene.cameras))]


def erode(m, r):
    if r <= 0:
        return m
    return cv2.erode(m.astype(np.uint8), np.ones((2 * r + 1, 2 * r + 1), np.uint8)) > 0


for name, occ in [("none", None), ("masks", 0), ("eroded1", 1), ("dilated1", -1)]:
    occluders = (
        None if occ is None else [(erode(regions[j], occ) if occ >= 0 else dilate(regions[j], 1)) for j in scene.train]
    )
    ious, ratio = [], []
    for i in scene.holes:
        if i not in scene.gt_depths:
            continue
        h = unseen_mask(
            scene.cameras[i],
            regions[i],
            scene.gt_depths[i],
            train,
            [scene.depths[j] for j in scene.train],
            0.01,
            occluders,
            None,
        )
        ious.append(iou(h, scene.holes[i]))
        ratio.append(h.sum() / max(1, scene.holes[i].sum()))
    print(name, f"IoU {np.mean(ious):.3f}", f"size/truth {np.mean(ratio):.2f}", np.round(ious, 2))
