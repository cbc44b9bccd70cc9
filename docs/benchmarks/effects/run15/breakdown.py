"""Where the error outside the true hole sits in a removal of a generated scene (issue 16): the revealed part (the
object's region some view saw), the true effect pixels our effect masks hit and miss, our masks beyond the truth,
and the rest. `python breakdown.py SCENE REMOVED` (REMOVED: a `remove` output folder of a run on SCENE)."""

import sys

import numpy as np

from engine.io.image_io import read_png
from engine.io.scene import load_scene


def parts_of(scene, removed: str, i: int) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]:
    """View i's squared error against gt/ and the disjoint parts of what lies outside its true hole."""
    name = scene.cameras[i].name
    image = read_png(f"{removed}/images/{name}").astype(float)
    error = ((image - scene.gt_images[i].astype(float)) ** 2).mean(-1)
    hole, region = scene.holes[i], scene.masks[i] == scene.target.id
    truth = read_png(f"{scene.root}/effects/{name}", "mask") > 0
    ours = read_png(f"{removed}/effects/{name}", "mask") > 0
    base = ~hole & ~region
    return error, {"revealed": region & ~hole, "effect hit": truth & ours & base,
                   "effect missed": truth & ~ours & base, "ours not effect": ours & ~truth & base,
                   "rest": base & ~truth & ~ours}, ~hole


def main(scene_dir: str, removed: str) -> None:
    scene = load_scene(scene_dir)
    sums: dict[str, list[float]] = {}
    for i in (i for i in scene.test if i in scene.gt_images):
        error, parts, outside = parts_of(scene, removed, i)
        for key, mask in [*parts.items(), ("outside", outside)]:
            total = sums.setdefault(key, [0.0, 0.0])
            total[0] += float(error[mask].sum())
            total[1] += float(mask.sum())
    for key, (error, pixels) in sums.items():
        psnr = 10 * np.log10(255 ** 2 / (error / max(pixels, 1)))
        print(f"{key:16s} px {int(pixels):7d} share of error {error / sums['outside'][0]:.2f} psnr {psnr:.2f}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
