"""A generated scene's images as a user's capture: pycolmap's own SfM, no masks, nothing the generator knew.

    .venv/bin/python scripts/make_capture.py --scene SCENE --out CAPTURE [--keep-truth]

Copies SCENE/images into CAPTURE/images and runs SfM on them (SIFT, exhaustive matching, incremental
mapping) with one SIMPLE_RADIAL camera of unknown focal length, as COLMAP's and capture apps' defaults
do: CAPTURE/sparse holds the largest model, in SfM's own frame and scale. `--keep-truth` also copies
what scores a result against the generator (gt/, holes/, unseen/, split.json less the views SfM dropped: all per
image, valid in any frame), never masks/. The tests and the README's "Your own capture" start from such
a folder. Engine Python.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import zlib  # noqa: F401,I001  -- before pycolmap, see engine.io.colmap_model
from pathlib import Path

import cv2  # noqa: F401

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from engine.formats.layout import SceneLayout  # noqa: E402


def make_capture(scene: Path, out: Path, keep_truth: bool = False) -> dict:
    import pycolmap

    source, target = SceneLayout(scene), SceneLayout(out)
    if out.exists():
        raise SystemExit(f"error: {out} exists: choose a new folder")
    shutil.copytree(source.images, target.images)
    if keep_truth:
        for folder in (source.gt, source.holes, source.unseen):
            if folder.is_dir():
                shutil.copytree(folder, out / folder.name)
    work = out / ".sfm"
    work.mkdir()
    reader = pycolmap.ImageReaderOptions()
    reader.camera_model = "SIMPLE_RADIAL"
    pycolmap.extract_features(work / "database.db", target.images, camera_mode=pycolmap.CameraMode.SINGLE,
                              reader_options=reader, device=pycolmap.Device.cpu)
    pycolmap.match_exhaustive(work / "database.db", device=pycolmap.Device.cpu)
    models = pycolmap.incremental_mapping(work / "database.db", target.images, work / "sparse")
    if not models:
        raise SystemExit(f"error: SfM registered none of the images of {scene}")
    best = models[max(models, key=lambda k: models[k].num_reg_images())]
    model_dir = target.sparse
    model_dir.mkdir(parents=True)
    best.write_binary(str(model_dir))
    registered = {image.name for image in best.images.values()}
    if keep_truth:  # the generator's split, less the views SfM could not register
        split = json.loads(source.split_json.read_text())
        target.split_json.write_text(json.dumps({k: [n for n in v if n in registered] for k, v in split.items()}))
    shutil.rmtree(work)
    report = {"images": len(list(target.images.iterdir())), "registered": best.num_reg_images(),
              "points": best.num_points3D(),
              "mean_reprojection_error_px": round(best.compute_mean_reprojection_error(), 3)}
    print(json.dumps(report))
    return report


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--keep-truth", action="store_true")
    args = parser.parse_args()
    make_capture(Path(args.scene), Path(args.out), args.keep_truth)
    return 0


if __name__ == "__main__":
    sys.exit(main())
