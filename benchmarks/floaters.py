"""What covers a trained capture's worst test views, and which rule for removing Gaussians would clear it.

    python benchmarks/floaters.py RUN OUT.json [--device cuda]

Why: on the skull capture four test views of nine (01, 09, 17, 25) render at 10-13 dB as one flat colour, in our
training and in a plain 3DGS one alike, while their neighbours train well; camera clearance (engine.train.
camera_clearance) at up to 3 sigma does not clear them, and the run folder does not come back from the GPU machine.
This reads the run where it was trained and writes, small:

- per test view (and every fourth training view, to see what a rule costs) the PSNR of the trained model;
- for each test view far below the rest, the Gaussians that cover most of it in front of the scene's centre: where
  they stand, how large, how opaque, how far from the nearest training camera, in how many training frustums;
- per candidate rule, how many Gaussians it removes and the same PSNRs without them (no training after).
"""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

import numpy as np
import torch

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from benchmarks.records import run_study_args  # noqa: E402
from engine.base.device import pick_device  # noqa: E402
from engine.edit.effects import colors_of  # noqa: E402
from engine.formats.cameras import Camera, project  # noqa: E402
from engine.metrics.evaluate import evaluate_views  # noqa: E402
from engine.train.background_floaters import background_floaters, view_change  # noqa: E402
from engine.train.camera_clearance import centres_of, holding_cameras  # noqa: E402
from engine.train.trained_run import load_run  # noqa: E402

BAD_GAP = 4.0  # dB below the test views' median: a view to explain
TOP = 12  # culprits listed per bad view


def footprint(camera: Camera, means: np.ndarray, radius: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each Gaussian's depth in `camera` and the share of the picture its 2-sigma disc covers (0 behind it)."""
    u, v, z = project(camera, means)
    r = 2 * camera.fx * radius / np.maximum(z, 1e-6)
    left, right = np.clip(u - r, 0, camera.width), np.clip(u + r, 0, camera.width)
    top, bottom = np.clip(v - r, 0, camera.height), np.clip(v + r, 0, camera.height)
    share = (right - left) * (bottom - top) / (camera.width * camera.height)
    return z, np.where(z > 0.01, share, 0.0)


def in_frustums(cameras: list[Camera], means: np.ndarray) -> np.ndarray:
    """How many of `cameras` hold each centre inside their picture, in front."""
    count = np.zeros(len(means), np.int32)
    for camera in cameras:
        u, v, z = project(camera, means)
        count += (z > 0.01) & (u >= 0) & (u < camera.width) & (v >= 0) & (v < camera.height)
    return count


def between(a: Camera, b: Camera) -> Camera:
    """A camera halfway between `a` and `b`, facing the mean of their viewing directions (a's intrinsics): a view
    the photographer passed on the way, which no training view holds."""
    centre = (a.center + b.center) / 2
    forward = (a.R[2] + b.R[2]) / np.linalg.norm(a.R[2] + b.R[2])
    down = a.R[1] + b.R[1] - forward * np.dot(a.R[1] + b.R[1], forward)
    down /= np.linalg.norm(down)
    rotation = np.stack([np.cross(down, forward), down, forward])
    return dataclasses.replace(a, name=f"{a.name}~{b.name}", R=rotation, t=-rotation @ centre)


def between_views(cameras: list[Camera]) -> list[Camera]:
    """One camera halfway between each training camera and its nearest neighbour (each pair once)."""
    centres = np.stack([c.center for c in cameras])
    pairs = set()
    for i, c in enumerate(centres):
        distances = np.linalg.norm(centres - c, axis=1)
        distances[i] = np.inf
        pairs.add(tuple(sorted((i, int(np.argmin(distances))))))
    return [between(cameras[i], cameras[j]) for i, j in sorted(pairs)]


def novel_view_floaters(gaussians: dict, train: list[Camera], sh_degree: int, device, ratios: tuple[float, ...]
                        ) -> dict[str, np.ndarray]:
    """Per ratio k, the Gaussians whose removal would change some view halfway between two training cameras more
    than k times as much as it changes any training view (and by more than a thousandth of a picture): what the
    training views cannot see but a view between them would (the skull's black Gaussians over the black
    background). `gaussians` already on `device`."""
    most_train = torch.zeros(len(gaussians["means"]), device=device)
    for camera in train:
        most_train = torch.maximum(most_train, view_change(gaussians, camera, sh_degree, device)[0])
    most_between = torch.zeros_like(most_train)
    for camera in between_views(train):
        most_between = torch.maximum(most_between, view_change(gaussians, camera, sh_degree, device)[0])
    floor = 1e-3 * train[0].width * train[0].height
    return {f"novel_view_change>{k}x_train": ((most_between > k * most_train) & (most_between > floor)).cpu().numpy()
            for k in ratios}


def psnrs(run, views: list[int], gaussians, device) -> dict[str, float]:
    """PSNR per view of `gaussians`, already on `device` (the run's classifier is moved there once)."""
    return evaluate_views(run.scene, views, gaussians, run.classifier.to(device), run.sh_degree,
                          device)["psnr_per_view"]


def without(gaussians: dict, drop: np.ndarray) -> dict:
    keep = torch.as_tensor(~np.asarray(drop, bool))
    return {k: v[keep] for k, v in gaussians.items()}


def main() -> int:
    args = run_study_args(__doc__)
    run, device = load_run(args.run), pick_device(args.device)
    scene, g = run.scene, run.gaussians
    train = [scene.cameras[i] for i in scene.train]
    means = g["means"].numpy().astype(np.float64)
    scales = torch.exp(g["scales"]).numpy()
    radius = scales.max(1)
    opacity = torch.sigmoid(g["opacities"].flatten()).numpy()
    colour = colors_of(g)
    centres = np.stack([c.center for c in train])
    nearest = np.full(len(means), np.inf)
    for c in centres:
        nearest = np.minimum(nearest, np.linalg.norm(means - c, axis=1))
    frustums = in_frustums(train, means)
    sampled = scene.train[::4]
    on_device = {k: v.to(device) for k, v in g.items()}
    base_test, base_train = psnrs(run, scene.test, on_device, device), psnrs(run, sampled, on_device, device)
    median = float(np.median(list(base_test.values())))
    culprits = {}
    for i in scene.test:
        camera = scene.cameras[i]
        if base_test[camera.name] > median - BAD_GAP:
            continue
        z, share = footprint(camera, means, radius)
        weight = share * opacity
        order = np.argsort(-weight)[:TOP]
        culprits[camera.name] = [{
            "index": int(k), "mean": np.round(means[k], 3).tolist(), "depth": round(float(z[k]), 3),
            "max_scale": round(float(radius[k]), 3), "scales": np.round(scales[k], 3).tolist(),
            "opacity": round(float(opacity[k]), 3), "colour": np.round(colour[k], 3).tolist(),
            "share_of_picture": round(float(share[k]), 3), "nearest_train_camera": round(float(nearest[k]), 3),
            "train_frustums": int(frustums[k]), "scale_over_nearest": round(float(radius[k] / nearest[k]), 3),
        } for k in order]
    angular = radius / np.maximum(nearest, 1e-6)
    rules = {f"scale_over_nearest_camera>{k}": angular > k for k in (0.05, 0.1, 0.2, 0.4)}
    rules.update({f"train_frustums<{k}": frustums < k for k in (1, 2, 4)})
    centre_t = centres_of(train)
    for sig in (2.0, 3.0):
        rules[f"holds_train_camera_{sig}_sigma"] = holding_cameras(
            g["means"], g["quats"], g["scales"], centre_t, sig).numpy()
    rules.update(novel_view_floaters(on_device, train, run.sh_degree, device, (3.0, 10.0)))
    for tolerance in (0.01, 0.03, 0.06):  # the engine's rule (train --background-floaters TOLERANCE)
        rules[f"background_floaters_{tolerance}"] = background_floaters(on_device, train, run.sh_degree, device,
                                                                        tolerance)
    results = {}
    for name, drop in rules.items():
        kept = {k: v.to(device) for k, v in without(g, drop).items()}
        test, trained = psnrs(run, scene.test, kept, device), psnrs(run, sampled, kept, device)
        results[name] = {"removed": int(drop.sum()), "test_psnr_mean": round(float(np.mean(list(test.values()))), 2),
                         "train_psnr_mean": round(float(np.mean(list(trained.values()))), 2), "test": test}
        print(name, results[name]["removed"], results[name]["test_psnr_mean"], results[name]["train_psnr_mean"])
    record = {"run": args.run, "gaussians": len(means),
              "base": {"test": base_test, "test_psnr_mean": round(float(np.mean(list(base_test.values()))), 2),
                       "train_sampled": base_train,
                       "train_psnr_mean": round(float(np.mean(list(base_train.values()))), 2)},
              "culprits": culprits, "rules": results,
              "scale_over_nearest_percentiles": np.round(np.percentile(angular, [50, 90, 99, 99.9]), 4).tolist()}
    Path(args.out).write_text(json.dumps(record, indent=1))
    print(args.out, "base test", record["base"]["test_psnr_mean"], "train", record["base"]["train_psnr_mean"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
