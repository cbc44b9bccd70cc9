"""Seconds per 1-megapixel view for every offline inpainter, as `inpaint` runs them (engine.inpaint.run's view
loop, each inpainter's own parallelism), RGB and depth, on real photos with a real object's hole.

    PYTHONPATH=. python benchmarks/inpaint_speed.py PHOTOS RESULTS [VIEWS]

Each of VIEWS (default 16) photos is resized to 1 megapixel; its hole is the salient object a photo is centred
on (engine.segment.salient's u2netp map above 0.5, grown by 5 px), what a capture's hole covers; its depth a
smooth slope. RESULTS/inpaint_speed.json: per inpainter the seconds per view (wall time over the views, workers
and their start included), the workers and how, the mean hole in pixels; inpainters that cannot run here
(weights or packages missing) with the reason.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import cv2
import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from engine.base.errors import InputError  # noqa: E402
from engine.base.versions import code_commit  # noqa: E402
from engine.inpaint.registry import Inpainter, classes, create  # noqa: E402
from engine.inpaint.run import InpaintConfig, _each_view, _workers  # noqa: E402
from engine.io.masks import dilate  # noqa: E402

MEGAPIXEL = 1_000_000
OFFLINE = ("telea", "navier-stokes", "fsr", "shiftmap", "exemplar", "lama")


class ViewFill:
    """One view's fill, RGB then depth, as engine.inpaint.run does (picklable for the worker processes)."""

    def __init__(self, inpainter: Inpainter, holes: list[np.ndarray], depth: np.ndarray) -> None:
        self.inpainter, self.holes, self.depth = inpainter, holes, depth

    def __call__(self, image: np.ndarray, k: int) -> None:
        self.inpainter.inpaint(image, self.holes[k], "rgb")
        self.inpainter.inpaint(self.depth, self.holes[k], "depth")


def views(photos: Path, count: int) -> tuple[list[np.ndarray], list[np.ndarray]]:
    from engine.segment.salient import SalientNet

    net = SalientNet()
    files = sorted(p for p in photos.iterdir() if p.suffix.lower() in (".jpg", ".jpeg", ".png"))
    files = [files[k] for k in np.linspace(0, len(files) - 1, min(count, len(files))).astype(int)]
    images, holes = [], []
    for path in files:
        image = cv2.imread(str(path))[..., ::-1]
        scale = (MEGAPIXEL / (image.shape[0] * image.shape[1])) ** 0.5
        image = np.ascontiguousarray(cv2.resize(image, (round(image.shape[1] * scale), round(image.shape[0] * scale)),
                                                interpolation=cv2.INTER_AREA))
        images.append(image)
        holes.append(dilate(net.probability(image) > 0.5, 5))
    return images, holes


def main() -> int:
    photos, results = Path(sys.argv[1]), Path(sys.argv[2])
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 16
    images, holes = views(photos, count)
    h, w = images[0].shape[:2]
    depth = np.fromfunction(lambda y, x: 2.0 + 0.001 * y + 0.0005 * x, (h, w), dtype=np.float32)
    record = {"commit": code_commit(), "photos": photos.parent.name if photos.name == "images" else photos.name,
              "views": len(images), "size": [w, h], "mean_hole_px": int(np.mean([m.sum() for m in holes])),
              "gpu": _gpu(), "inpainters": {}}
    for name in OFFLINE:
        if name not in classes():
            continue
        try:
            inpainter = create(name)
            inpainter.inpaint(images[0][:64, :64], holes[0][:64, :64], "rgb")  # loads weights, imports packages
        except (InputError, AttributeError, ImportError) as exc:
            record["inpainters"][name] = {"unavailable": str(exc).splitlines()[0][:200]}
            continue
        workers, parallel = _workers(InpaintConfig(inpainter=name), inpainter)
        job = ViewFill(inpainter, holes, depth)
        start = time.perf_counter()
        for _ in _each_view(job, [(image, k) for k, image in enumerate(images)], workers, parallel):
            pass
        seconds = time.perf_counter() - start
        record["inpainters"][name] = {"seconds_per_view": round(seconds / len(images), 3), "workers": workers,
                                      "parallel": parallel}
        print(name, record["inpainters"][name], flush=True)
    results.mkdir(parents=True, exist_ok=True)
    (results / "inpaint_speed.json").write_text(json.dumps(record, indent=1))
    return 0


def _gpu() -> str | None:
    import torch

    return torch.cuda.get_device_name() if torch.cuda.is_available() else None


if __name__ == "__main__":
    sys.exit(main())
