"""What a removal left where the object stood: the remaining Gaussians that fall inside the object's masks (its
region in removed/masks, dilated as removal's hull test dilates it) in at least half of the training views that
frame them, which the hull test (nine in ten) kept. Per share band: how many, their opacity, largest scale, colour
and height over the support plane removal fitted (in units of the scene's camera distance), so a panel left on a
wall or a shell left around a statue can be told from the support itself.

    PYTHONPATH=. python benchmarks/leftovers.py RUN OUT.json
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import torch

from engine.edit.removal import RemovalConfig
from engine.formats.layout import RunLayout
from engine.formats.splat_ply import SH_C0
from engine.io.image_io import read_png
from engine.io.masks import dilate
from engine.io.ply_io import load_ply
from engine.io.visibility import inside_visual_hull
from engine.train.trained_run import load_run_scene

SHARES = (0.5, 0.7, 0.8, 0.9)  # lower edges of the bands reported (0.9 and up: what the hull test removes)


def describe(chosen: np.ndarray, gaussians: dict, plane: list[float] | None, scale: float) -> dict:
    """Counts and quartiles of the `chosen` Gaussians' opacity, largest scale, colour and height off the plane."""
    if not chosen.any():
        return {"count": 0}
    opacity = torch.sigmoid(gaussians["opacities"][chosen]).numpy()
    size = torch.exp(gaussians["scales"][chosen]).max(dim=1).values.numpy() / scale
    rgb = np.clip(gaussians["sh0"][chosen].reshape(-1, 3).numpy() * SH_C0 + 0.5, 0, 1)
    out = {"count": int(chosen.sum()), "opacity_q": np.quantile(opacity, [0.25, 0.5, 0.75]).round(3).tolist(),
           "opaque_share": round(float((opacity > 0.5).mean()), 3),
           "largest_scale_q": np.quantile(size, [0.25, 0.5, 0.75]).round(4).tolist(),
           "mean_rgb": rgb.mean(axis=0).round(3).tolist()}
    if plane is not None:
        n, d = np.asarray(plane[:3]), plane[3]
        height = (gaussians["means"][chosen].numpy() @ n + d) / scale
        out["height_q"] = np.quantile(height, [0.1, 0.25, 0.5, 0.75, 0.9]).round(4).tolist()
    return out


def main(run: Path, out: Path) -> None:
    layout = RunLayout(run)
    scene = load_run_scene(run)
    gaussians = load_ply(layout.removed.point_cloud)
    report = json.loads(layout.removed.report.read_text())
    cameras = [scene.cameras[i] for i in scene.train]
    masks = [dilate(read_png(layout.removed.masks / c.name, "mask", c.size) > 0, RemovalConfig.hull_dilate)
             for c in cameras]
    means = gaussians["means"].numpy()
    scale = float(np.median([np.linalg.norm(c.center) for c in cameras]))
    plane = report.get("support_plane")
    bands, below = {}, np.zeros(len(means), bool)
    for share in reversed(SHARES):
        inside = inside_visual_hull(means, cameras, masks, share=share)
        bands[f"share_{share}"] = describe(inside & ~below, gaussians, plane, scale)
        below |= inside
    result = {"run": str(run), "gaussians": len(means), "support_plane": plane, "camera_distance": scale,
              "footprint": report.get("footprint"), "selected_by": report.get("selected_by"), "bands": bands}
    out.write_text(json.dumps(result, indent=1))
    print(json.dumps({k: v["count"] for k, v in bands.items()}))


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]))
