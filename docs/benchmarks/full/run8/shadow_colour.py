"""Whether the trained scene holds the object's shadow in its true colour (issue 16's green relit disc): per test
view, over the generator's exact effect region (effects/), the base run's render against images/ (what training
saw) and gt/ against images/ (the relight the removal should apply), as mean-colour ratios R, G, B.

    python docs/benchmarks/full/run8/shadow_colour.py SCENE RENDERS   (RENDERS: `engine render` of the base run)

Run 8's renders are base.tgz from device.sh's collect (not committed, 7 MB); the output is shadow_colour.txt.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from engine.io.image_io import read_png

MIN_PIXELS = 200  # views whose effect region is smaller say little about its colour


def main() -> None:
    scene, renders = Path(sys.argv[1]), Path(sys.argv[2])
    for render in sorted(renders.glob("*.png")):
        effect = scene / "effects" / render.name
        if not effect.is_file():
            continue
        region = read_png(effect, kind="mask") > 0
        if region.sum() < MIN_PIXELS:
            continue
        seen = read_png(scene / "images" / render.name)[region].astype(float).mean(0)
        trained = read_png(render)[region].astype(float).mean(0)
        truth = read_png(scene / "gt" / render.name)[region].astype(float).mean(0)
        print(f"{render.name} {int(region.sum()):6d} px  render/images {np.round(trained / seen, 3)}  "
              f"gt/images {np.round(truth / seen, 3)}  images {np.round(seen, 1)}")


if __name__ == "__main__":
    main()
