"""Issue 16's livingroom: what each method put in the true hole, cropped, and how its colour compares with gt/.

The scene's holes/ are a few hundred to 1,500 pixels of a 640x480 test view, too small to judge in the benchmark's
sheets. This crops every test view around its hole (grown by MARGIN px) from gt/, the removed scene's renders and
each cell's renders, writes them as one PNG per view (columns in that order, scaled up 3x, the hole's outline in
white), and prints per method and view the m-PSNR and the mean colour in the hole against gt/'s, so a fill that
is the wrong colour shows apart from one that is the right colour without the texture.

    python3 hole_crops.py SCENE RUN OUT
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import cv2
import numpy as np

MARGIN = 40
SCALE = 3


def box(mask: np.ndarray) -> tuple[slice, slice]:
    ys, xs = np.nonzero(mask)
    h, w = mask.shape
    return (slice(max(ys.min() - MARGIN, 0), min(ys.max() + MARGIN + 1, h)),
            slice(max(xs.min() - MARGIN, 0), min(xs.max() + MARGIN + 1, w)))


def main(scene: Path, run: Path, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    test = json.loads((scene / "split.json").read_text())["test"]
    columns = {"gt": scene / "gt", "unfilled": run / "removed" / "images"}
    columns |= {c.name: c / "renders" for c in sorted((run / "complete").iterdir()) if (c / "renders").is_dir()}
    rows = {}
    for view in test:
        hole = cv2.imread(str(scene / "holes" / view), cv2.IMREAD_GRAYSCALE) > 127
        if not hole.any():
            continue
        crop = box(hole)
        truth = cv2.imread(str(scene / "gt" / view))[..., ::-1].astype(np.float64) / 255
        tiles = []
        for label, folder in columns.items():
            image = cv2.imread(str(folder / view))
            if image is None:
                continue
            rgb = image[..., ::-1].astype(np.float64) / 255
            mse = ((rgb[hole] - truth[hole]) ** 2).mean()
            rows.setdefault(label, {})[view] = (10 * np.log10(1 / max(mse, 1e-12)), rgb[hole].mean(0))
            tile = cv2.resize(image[crop], None, fx=SCALE, fy=SCALE, interpolation=cv2.INTER_NEAREST)
            edge = cv2.resize(hole[crop].astype(np.uint8), None, fx=SCALE, fy=SCALE, interpolation=cv2.INTER_NEAREST)
            contours, _ = cv2.findContours(edge, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
            cv2.drawContours(tile, contours, -1, (255, 255, 255), 1)
            cv2.putText(tile, label[:22], (3, 12), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (255, 255, 255), 1)
            tiles.append(tile)
        cv2.imwrite(str(out / view), np.concatenate(tiles, axis=1))
    for label, views in rows.items():
        psnr = np.mean([p for p, _ in views.values()])
        colour = np.mean([c - rows["gt"][v][1] for v, (_, c) in views.items()], axis=0)
        print(f"{label:34s} m-PSNR {psnr:6.2f}  mean colour - gt's (R, G, B) {np.round(colour, 3)}")


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3]))
