"""The support's colour in the ring just past a removed object's footprint (underside.in_ring: 1 to 1.5 footprint
radii, within a tenth of one of the support's plane), read five ways, against the colour removal gave the crater
and the patch it laid (removal.json's effects.underside.colour):
  truth    gt/ (the scene without the object) at its test views, where gt/'s depth puts a pixel in the ring (a scene
           packed by pack_scene.py has no gt_depth/: NaN, and a line that says so);
  removed  the removed scene's renders of the test views, where their depth puts a pixel in the ring;
  base     the trained run's Gaussians in the ring, their base colour (the SH DC term: what removal reads);
  seen     the same Gaussians as the training views render them (every SH band, averaged over the views);
  opacity  those Gaussians' mean opacity (a faint support renders darker over black than its colour).
Why: on the GPU judge at 3067ef9 the patch came out lighter than gt/'s ring (statue_s55 +0.04, livingroom_s8 R
+0.08), the tiny CPU runs' within 0.03; whether the higher SH bands, the faint support or the relights hold the
difference decides what the patch should take. Trimmed means (effects.trimmed_mean), in [0, 1].

    PYTHONPATH=. python benchmarks/ring_colour.py RUN SCENE [--resolution N]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import torch

from benchmarks.records import option
from engine.capture.scene import load_scene
from engine.edit.effects import colors_of, trimmed_mean
from engine.edit.underside import in_ring
from engine.formats.cameras import backproject
from engine.formats.layout import RunLayout
from engine.io.image_io import exr_name, read_depth, read_png
from engine.render.rasterize import CameraTensors, view_colours
from engine.train.trained_run import load_splats


class Ring:
    """The ring about the footprint that removal.json reports."""

    def __init__(self, report: dict):
        plane, footprint = report["support_plane"], report["footprint"]
        self.normal, self.offset = np.asarray(plane[:3]), float(plane[3])
        self.radius = float(footprint["radius"])
        centre = np.asarray(footprint["centre"])
        self.centre = centre - (centre @ self.normal + self.offset) * self.normal

    def holds(self, points: np.ndarray) -> np.ndarray:
        height = points @ self.normal + self.offset
        across = np.linalg.norm(points - np.outer(height, self.normal) - self.centre, axis=1)
        return in_ring(height, across, self.radius)


def pixels_in_ring(ring: Ring, camera, depth: np.ndarray, image: np.ndarray) -> np.ndarray:
    """(P, 3) the colours of `image` where `depth` (z, inf or 0 where none) puts its pixel in the ring."""
    ys, xs = np.nonzero(np.isfinite(depth) & (depth > 0))
    inside = ring.holds(backproject(camera, xs + 0.5, ys + 0.5, depth[ys, xs]))
    return image[ys[inside], xs[inside], :3] / 255.0


def seen_colours(gaussians, picked: np.ndarray, cameras: list, sh_degree: int) -> np.ndarray:
    """(P, 3) the `picked` Gaussians' colours as each camera renders them (rasterize.view_colours), averaged."""
    idx = torch.as_tensor(np.flatnonzero(picked))
    some = {k: gaussians[k][idx] for k in ("means", "sh0", "shN")}
    total = sum(view_colours(some, CameraTensors.from_camera(c, "cpu"), sh_degree, "reference") for c in cameras)
    return (total / len(cameras)).numpy()


def main(argv: list[str]) -> None:
    resolution, args = option(argv, "--resolution")
    run, scene = Path(args[0]), load_scene(Path(args[1]), int(resolution or 1), depth=True)
    removed = RunLayout(run).removed
    report = json.loads(removed.report.read_text())
    ring = Ring(report)
    truth, shown = [], []
    for i in scene.test:
        name, camera = scene.cameras[i].name, scene.cameras[i]
        if i in scene.gt_images and i in scene.gt_depths:
            truth.append(pixels_in_ring(ring, camera, scene.gt_depths[i], scene.gt_images[i]))
        shown.append(pixels_in_ring(ring, camera, read_depth(removed.depth / exr_name(name)),
                                    read_png(removed.images / name)))
    gaussians, sh_degree = load_splats(run)
    picked = ring.holds(gaussians["means"].numpy())
    opacity = torch.sigmoid(gaussians["opacities"]).numpy().reshape(-1)[picked]
    laid = (report.get("effects") or {}).get("underside") or {}
    rows = {"removal's": np.asarray(laid.get("colour", [np.nan] * 3)),
            "truth": trimmed_mean(np.concatenate(truth)) if truth else np.full(3, np.nan),
            "removed": trimmed_mean(np.concatenate(shown)),
            "base": trimmed_mean(colors_of(gaussians)[picked]),
            "seen": trimmed_mean(seen_colours(gaussians, picked, [scene.cameras[i] for i in scene.train], sh_degree))}
    print(f"{run}: ring of {int(picked.sum())} Gaussians, mean opacity {opacity.mean():.3f}, "
          f"laid {report.get('laid')}")
    if not truth:  # benchmarks/pack_scene.py leaves gt_depth/ out of what it sends to the GPU machine
        print(f"  truth: {args[1]} has no gt_depth/ for its test views: run this again on the unpacked scene")
    for what, colour in rows.items():
        print(f"  {what:10s} {np.round(colour, 3)}  minus truth {np.round(colour - rows['truth'], 3)}")


if __name__ == "__main__":
    main(sys.argv[1:])
