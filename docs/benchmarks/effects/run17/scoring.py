"""The effects experiments' one score of a removed scene (run16/overshoot.py, run17/variants.py): its test views
against gt/, PSNR outside the true hole and in the true effect pixels (mean over the views, as removal.json's
psnr_outside_hole), and the effect pixels' removed / gt/ ratio per channel (25th, 50th, 75th percentile)."""

import numpy as np

from engine.edit import removal


def score(run, gaussians, name: str, device) -> None:
    scene = run.scene
    tests = [i for i in scene.test if i in scene.gt_images and i in scene.holes]
    pictures = list(removal.render_pictures(gaussians, [scene.cameras[i] for i in tests], run.sh_degree, device,
                                            depth=False))
    outside, effect, ratios = [], [], []
    for i, picture in zip(tests, pictures, strict=True):
        rgb, gt = picture.rgb.astype(float), scene.gt_images[i].astype(float)
        hole = scene.holes[i]
        outside.append(((rgb - gt)[~hole] ** 2).mean())
        if i in scene.effects and scene.effects[i].any():
            e = scene.effects[i] & ~hole
            effect.append(((rgb - gt)[e] ** 2).mean())
            ratios.append((rgb[e] + 1) / (gt[e] + 1))

    def db(mse: list) -> float:
        return round(float(np.mean([10 * np.log10(255 ** 2 / max(m, 1e-9)) for m in mse])), 2) if mse else float("nan")
    pct = np.percentile(np.concatenate(ratios), [25, 50, 75], 0).round(3).tolist() if ratios else None
    print(f"{name:40s} outside the hole {db(outside)} dB, effect pixels {db(effect)} dB, removed/gt {pct}", flush=True)
