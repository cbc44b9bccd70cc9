"""Score removals of one scene against its exact data: PSNR outside the true hole (removal.json), and over the exact
effect region of the test views (outside the holes) the removed/gt ratio of its interior, its edge band, the ring
just past it, and its brighter and darker halves by gt/'s luminance, with the texture's contrast against gt/'s;
then where the error outside the true hole lies, over every test view with a hole: the rim just past the hole
(RIM_SHARE of the width: where the support ends at the hole, seen by some view yet rendered part transparent over
black), the effect region, the rest, each with its share of the pixels and of the squared error and the PSNR
outside the hole were that part right (what mending it alone could reach); a picture of the first test view
with an effect: each removal, then gt/. With --resolution N, the scene at 1/N of its size, as a run trained at
`--resolution N` read it (engine.capture.downscale).

    PYTHONPATH=. python benchmarks/removal_score.py SCENE REMOVED... [--picture OUT.png] [--resolution N]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import cv2
import numpy as np

from benchmarks.records import option
from engine.capture.downscale import downscaled_scene
from engine.edit.effects import LUMA
from engine.formats.layout import RemovedLayout, SceneLayout
from engine.io.image_io import read_png
from engine.io.masks import dilate
from engine.metrics.image_metrics import psnr_from_mse

RIM_SHARE = 0.0125  # the rim's width as a share of the image width: 4 px at 320 (a tiny CPU run's rim, 2 px at
# 160, held 27% of statue_s55's squared error outside the true hole on 1% of its pixels)


def load(path: Path) -> np.ndarray:
    return read_png(path) / 255.0


def parts(effect: np.ndarray, hole: np.ndarray) -> dict[str, np.ndarray]:
    kernel = np.ones((3, 3), np.uint8)
    inner = cv2.erode(effect.astype(np.uint8), kernel, iterations=2) > 0
    ring = (cv2.dilate(effect.astype(np.uint8), kernel, iterations=2) > 0) & ~effect
    return {"interior": inner & ~hole, "edge": effect & ~inner & ~hole, "ring past it": ring & ~hole}


def score(scene: Path, removed: Path, views: list[str]) -> None:
    report = json.loads((RemovedLayout(removed).report).read_text())
    print(f"{removed}: outside the true hole {report['psnr_outside_hole']:.3f} dB, revealed "
          f"{report['psnr_revealed']:.3f} dB, shadow {report['effects']['shadow']}")
    pooled: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
    for name in views:
        effect = read_png(SceneLayout(scene).effects / name, "mask") > 0
        hole = read_png(SceneLayout(scene).holes / name, "mask") > 0
        gt, out = load(SceneLayout(scene).gt / name), load(RemovedLayout(removed).images / name)
        for part, mask in parts(effect, hole).items():
            pooled.setdefault(part, []).append((out[mask], gt[mask]))
    for part, pairs in pooled.items():
        out, gt = np.concatenate([p[0] for p in pairs]), np.concatenate([p[1] for p in pairs])
        psnr = psnr_from_mse(float(((out - gt) ** 2).mean()))
        print(f"  {part:13s} {len(out):7d} px  removed/gt {(out.mean(0) / gt.mean(0)).round(3)}  {psnr:.2f} dB")
        if part == "interior":
            y = gt @ LUMA
            for half, sel in (("brighter half", y > np.median(y)), ("darker half", y <= np.median(y))):
                print(f"    {half:13s} removed/gt {(out[sel].mean(0) / gt[sel].mean(0)).round(3)}")
            print(f"    texture contrast (std of luminance) against gt/: {(out @ LUMA).std() / y.std():.3f}")


def error_outside(scene: Path, removed: Path) -> None:
    """Each part's share of the pixels and squared error outside the true hole, and the PSNR outside it (the mean
    over views, as removal.json's) were that part's error nil."""
    layout, base, shares, psnrs = SceneLayout(scene), [], {}, {}
    for name in json.loads(layout.split_json.read_text())["test"]:
        hole = read_png(layout.holes / name, "mask") > 0
        if not hole.any():
            continue
        error = ((load(RemovedLayout(removed).images / name) - load(layout.gt / name)) ** 2).mean(-1)
        effect = (read_png(layout.effects / name, "mask") > 0 if (layout.effects / name).is_file()
                  else np.zeros_like(hole))
        rim = dilate(hole, max(1, round(hole.shape[1] * RIM_SHARE))) & ~hole
        outside = ~hole
        base.append(psnr_from_mse(float(error[outside].mean())))
        for part, mask in (("rim", rim), ("effect", effect & outside & ~rim), ("rest", outside & ~rim & ~effect)):
            shares.setdefault(part, []).append((mask.sum() / outside.sum(), error[mask].sum() / error[outside].sum()))
            psnrs.setdefault(part, []).append(psnr_from_mse(float(error[outside & ~mask].sum() / outside.sum())))
    print(f"  outside the true hole {np.mean(base):.2f} dB; were a part right:")
    for part, values in shares.items():
        pixels, error = np.mean(values, 0)
        print(f"    {part:7s} {pixels:6.1%} of the pixels, {error:6.1%} of the error: {np.mean(psnrs[part]):.2f} dB")


def main(args: list[str]) -> None:
    picture, args = option(args, "--picture")
    resolution, args = option(args, "--resolution")
    scene, removals = downscaled_scene(Path(args[0]), int(resolution or 1)), [Path(a) for a in args[1:]]
    views = [n for n in json.loads((SceneLayout(scene).split_json).read_text())["test"]
             if (SceneLayout(scene).effects / n).is_file() and read_png(SceneLayout(scene).effects / n, "mask").any()]
    for removed in removals:
        score(scene, removed, views)
        error_outside(scene, removed)
    if picture and views:
        row = [cv2.imread(str(RemovedLayout(r).images / views[0])) for r in removals]
        row.append(cv2.imread(str(SceneLayout(scene).gt / views[0])))
        cv2.imwrite(picture, cv2.hconcat(row))


if __name__ == "__main__":
    main(sys.argv[1:])
