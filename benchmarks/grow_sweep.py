"""How far to grow the hole masks before inpainting, on a finished removal: each test view's removed render
filled in its `holes` mask grown by D px, m-PSNR against the truth (gt/) in the true hole (holes/), beside the
unfilled render's. The 2D stage alone, on the 3D pipeline's own renders (a removal's leftovers at the hole's
border included, which is what growing is for); what a completion adds on top is the held-out table's.

Also whether to keep what the removed scene already renders there: where its surface in the true hole lies on the
support plane `remove` found (within --plane-tol of the plane's depth), 3DGS has carried the support on under the
object (held-out statue_s100 on an H200: the unfilled render scores above every fill). `keep+D=N` is the fill
with those pixels left as rendered; `on_plane` their share of the true hole, with the unfilled and the fill's
m-PSNR on them and on the rest. `colour<Z+D=N` keeps instead the pixels whose rendered colour lies within Z
standard deviations (per channel, 4 levels at least) of the ring just outside the grown mask (6 px): what already
looks like the surface around it (four test views of the H200 runs at 5ebcf5e / 8f8400b, Z = 1: livingroom 26.61,
statue 25.08, tabletop 23.89, wall 31.63 against the fill's 22.29, 15.28, 24.26, 33.59).

    PYTHONPATH=. python benchmarks/grow_sweep.py RUN... [--grow 0 1 3 6 13] [--inpainter telea] [--holes DIR]
        [--json OUT]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from engine.edit.holes import iou
from engine.edit.support_plane import plane_along_rays, removal_plane
from engine.formats.cameras import Camera
from engine.formats.layout import HolesLayout, RunLayout
from engine.inpaint.keep import like_ring
from engine.inpaint.registry import create
from engine.io.image_io import exr_name, read_depth, read_png
from engine.io.masks import dilate
from engine.metrics.image_metrics import masked_psnr
from engine.train.trained_run import load_run_scene


def on_plane(camera: Camera, depth: np.ndarray, plane: tuple[np.ndarray, float] | None, tol: float) -> np.ndarray:
    """(H, W) bool: pixels whose rendered surface lies within `tol` (relative) of the plane along their ray."""
    if plane is None:
        return np.zeros(depth.shape, bool)
    ys, xs = np.indices(depth.shape).reshape(2, -1)
    _, z_plane = plane_along_rays(camera, ys, xs, plane)
    z = depth.reshape(-1)
    near = np.isfinite(z) & (z_plane > 0) & (np.abs(z - z_plane) <= tol * np.abs(z_plane))
    return near.reshape(depth.shape)


def sweep(run: Path, grows: list[int], inpainter: str, plane_tol: float = 0.02, keep_z: tuple = (0.5, 1.0),
          holes: Path | None = None) -> dict:
    """Per grow (and 'unfilled', and each grow keeping the on-plane render), the mean over test views with a true
    hole of m-PSNR in it, and the grown masks' IoU with the true hole; the on-plane share and split scores (at the
    last grow). `holes`: a holes folder other than RUN/holes (a variant of the stage), relative to the run."""
    scene, layout = load_run_scene(run), RunLayout(run)
    holes_of = HolesLayout(run / holes) if holes else layout.holes
    fill, plane = create(inpainter), removal_plane(layout.removed)
    scores: dict[str, list[float]] = {"unfilled": []}
    for i in scene.test:
        truth_hole = scene.holes.get(i)
        if truth_hole is None or truth_hole.sum() < 20 or i not in scene.gt_images:
            continue
        camera, truth = scene.cameras[i], scene.gt_images[i]
        removed = read_png(layout.removed.images / camera.name)
        hole = read_png(holes_of.mask(camera.name), kind="mask") > 0
        kept = on_plane(camera, read_depth(layout.removed.depth / exr_name(camera.name)), plane, plane_tol)
        scores["unfilled"].append(masked_psnr(removed, truth, truth_hole))
        scores.setdefault("on_plane", []).append(float((kept & truth_hole).sum() / truth_hole.sum()))
        for d in grows:
            grown = dilate(hole, d)
            filled = fill.inpaint(removed, grown, "rgb")
            scores.setdefault(f"D={d}", []).append(masked_psnr(filled, truth, truth_hole))
            scores.setdefault(f"iou D={d}", []).append(iou(grown, truth_hole))
            scores.setdefault(f"keep+D={d}", []).append(
                masked_psnr(np.where(kept[..., None], removed, filled), truth, truth_hole))
            for z in keep_z:
                alike = like_ring(removed, grown, z)
                scores.setdefault(f"colour<{z}+D={d}", []).append(
                    masked_psnr(np.where(alike[..., None], removed, filled), truth, truth_hole))
        for part, mask in (("on", truth_hole & kept), ("off", truth_hole & ~kept)):  # `filled`: the last grow's
            if mask.sum() >= 20:
                scores.setdefault(f"unfilled_{part}_plane", []).append(masked_psnr(removed, truth, mask))
                scores.setdefault(f"D={grows[-1]}_{part}_plane", []).append(masked_psnr(filled, truth, mask))
    return {k: round(float(np.mean(v)), 3) for k, v in scores.items() if v} | {"views": len(scores["unfilled"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path)
    parser.add_argument("--grow", nargs="+", type=int, default=[0, 1, 3, 6, 13])
    parser.add_argument("--inpainter", default="telea")
    parser.add_argument("--plane-tol", type=float, default=0.02, help="on the plane: within this share of its depth")
    parser.add_argument("--keep-z", type=float, nargs="*", default=[0.5, 1.0],
                        help="colour<Z: keep pixels within Z standard deviations of the ring's colours")
    parser.add_argument("--holes", type=Path, help="the holes folder to grow, relative to each run (default holes)")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    table = {}
    for run in args.runs:
        table[str(run)] = sweep(run, args.grow, args.inpainter, args.plane_tol, tuple(args.keep_z), args.holes)
        print(run, table[str(run)], flush=True)
    if args.json:
        args.json.write_text(json.dumps({"inpainter": args.inpainter, "plane_tol": args.plane_tol, "runs": table},
                                        indent=1))


if __name__ == "__main__":
    main()
