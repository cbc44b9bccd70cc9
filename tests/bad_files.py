"""Seeded malformed inputs for every reader, read in a child process whose memory is capped.

    python tests/bad_files.py DIR COUNT SEED      # prints one JSON summary line

DIR holds one valid file per reader (`write_seeds`); each is mutated COUNT times (bytes flipped, inserted,
cut, text numbers swapped for huge, zero, negative or non-finite ones, nesting deepened) and read again.
A read must end in the result or in InputError; every other exception (MemoryError included, under the
cap the test sets) is an escape, listed with the reader, the mutation and its message.
"""

from __future__ import annotations

import json
import re
import sys
import traceback
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

DEBUG = False
NUMBERS = [b"0", b"-1", b"1e400", b"NaN", b"Infinity", b"4294967296", b"1e30", b"256", b"0.5", b"99999999999"]


def write_seeds(folder: Path) -> None:
    """One small valid file per reader."""
    import torch

    from engine.formats.cameras import Camera, write_cameras_json
    from engine.io.colmap_model import ColmapModel, write_model
    from engine.io.image_io import write_depth, write_png
    from engine.io.ply_io import save_classifier, save_ply

    rng = np.random.default_rng(0)
    n = 40
    gaussians = {"means": torch.randn(n, 3), "quats": torch.randn(n, 4), "scales": torch.randn(n, 3) - 3,
                 "opacities": torch.randn(n), "sh0": torch.randn(n, 1, 3), "shN": torch.randn(n, 3, 3),
                 "identity": torch.randn(n, 16)}
    folder.mkdir(parents=True, exist_ok=True)
    save_ply(folder / "splat.ply", gaussians)
    save_classifier(folder / "classifier.npz", torch.nn.Linear(16, 4))
    cameras = [Camera(name=f"{i:04d}.png", width=32, height=24, fx=30.0, fy=30.0, cx=16.0, cy=12.0,
                      R=np.eye(3), t=np.array([0.1 * i, 0.0, 3.0])) for i in range(3)]
    points = rng.normal(size=(30, 3))
    model = ColmapModel(cameras=cameras, points=points, colors=rng.integers(0, 256, (30, 3), dtype=np.uint8),
                        observations=[[(0, 3.0, 4.0), (1, 5.0, 6.0)] for _ in range(30)])
    write_model(folder / "bin", model)
    write_text_model(folder / "txt", model)
    write_depth(folder / "depth.exr", rng.uniform(1, 5, (24, 32)).astype(np.float32))
    write_png(folder / "image.png", rng.integers(0, 256, (24, 32, 3), dtype=np.uint8))
    write_png(folder / "mask.png", rng.integers(0, 3, (24, 32), dtype=np.uint8))
    write_cameras_json(cameras, folder / "cameras.json")
    (folder / "objects.json").write_text(json.dumps([{"id": 1, "name": "plush", "target": True},
                                                      {"id": 2, "name": "box", "target": False}]))


def write_text_model(folder: Path, model) -> None:
    """COLMAP's text layout (cameras.txt, images.txt, points3D.txt) of `model`."""
    folder.mkdir(parents=True, exist_ok=True)
    from engine.formats.cameras import Camera  # noqa: F401  -- the model's cameras

    lines = ["# Camera list"] + [f"{i + 1} PINHOLE {c.width} {c.height} {c.fx} {c.fy} {c.cx} {c.cy}"
                                 for i, c in enumerate(model.cameras)]
    (folder / "cameras.txt").write_text("\n".join(lines) + "\n")
    lines = ["# Image list"]
    for i, c in enumerate(model.cameras):
        lines += [f"{i + 1} 1 0 0 0 {c.t[0]} {c.t[1]} {c.t[2]} {i + 1} {c.name}", ""]
    (folder / "images.txt").write_text("\n".join(lines) + "\n")
    lines = ["# 3D point list"] + [f"{k + 1} {p[0]} {p[1]} {p[2]} {c[0]} {c[1]} {c[2]} 0.5"
                                   for k, (p, c) in enumerate(zip(model.points, model.colors, strict=True))]
    (folder / "points3D.txt").write_text("\n".join(lines) + "\n")


def readers(folder: Path) -> dict[str, tuple[Path, object]]:
    """Reader name -> (its valid seed file, a call reading a path the way the engine does)."""
    from engine.formats import colmap_files
    from engine.formats.cameras import read_cameras_json
    from engine.formats.checks import read_json
    from engine.io.image_io import read_depth, read_png
    from engine.io.ply_io import load_classifier, load_ply

    out = {"ply": (folder / "splat.ply", load_ply), "classifier": (folder / "classifier.npz", load_classifier),
           "exr": (folder / "depth.exr", read_depth), "png": (folder / "image.png", read_png),
           "mask": (folder / "mask.png", lambda p: read_png(p, kind="mask")),
           "cameras.json": (folder / "cameras.json", read_cameras_json), "objects.json": (folder / "objects.json",
                                                                                           read_json)}
    for kind in ("bin", "txt"):
        out[f"cameras.{kind}"] = (folder / kind / f"cameras.{kind}", colmap_files.read_cameras)
        out[f"images.{kind}"] = (folder / kind / f"images.{kind}", colmap_files.read_images)
        out[f"points3D.{kind}"] = (folder / kind / f"points3D.{kind}", colmap_files.read_points)
    return out


def mutate(data: bytes, rng: np.random.Generator) -> tuple[str, bytes]:
    """One random corruption of `data`, and its name."""
    kind = str(rng.choice(["flip", "insert", "cut", "number", "nest", "header"] if _texty(data) else
                      ["flip", "insert", "cut", "flip", "header", "zeros"]))
    at = int(rng.integers(0, max(len(data), 1)))
    if kind == "flip":
        return kind, data[:at] + bytes([int(rng.integers(0, 256))]) + data[at + 1:]
    if kind == "insert":
        return kind, data[:at] + bytes([int(rng.integers(0, 256))]) + data[at:]
    if kind == "cut":
        return kind, data[:at]
    if kind == "zeros":
        return kind, data[:at] + bytes(min(64, len(data) - at)) + data[at + 64:]
    if kind == "header":  # rewrite a number in the first 300 bytes (PLY counts, npy shapes, COLMAP counts)
        head = data[:300]
        found = list(re.finditer(rb"\d+", head))
        if found:
            m = found[int(rng.integers(0, len(found)))]
            value = NUMBERS[int(rng.integers(0, len(NUMBERS)))]
            return kind, data[:m.start()] + value + data[m.end():]
        return kind, data[:at] + np.uint64(rng.integers(0, 2**62)).tobytes() + data[at + 8:]
    if kind == "number":
        found = list(re.finditer(rb"-?\d+(\.\d+)?(e-?\d+)?", data))
        if found:
            m = found[int(rng.integers(0, len(found)))]
            return kind, data[:m.start()] + NUMBERS[int(rng.integers(0, len(NUMBERS)))] + data[m.end():]
        return kind, data
    depth = int(rng.choice([40, 2000]))  # nest
    return kind, b"[" * depth + data + b"]" * depth


def _texty(data: bytes) -> bool:
    return data[:1] in (b"[", b"{", b"#") or data[:1].isdigit()


def run(folder: Path, count: int, seed: int) -> dict:
    from engine.base.errors import InputError

    rng = np.random.default_rng(seed)
    summary = {"inputs": 0, "refused": 0, "accepted": 0, "escapes": []}
    work = folder / "mutated"
    work.mkdir(exist_ok=True)
    for name, (path, read) in readers(folder).items():
        data = path.read_bytes()
        for k in range(count):
            kind, bad = mutate(data, rng)
            target = work / path.parent.name / path.name if path.parent != folder else work / path.name
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(bad)
            if DEBUG:
                print(name, kind, k, file=sys.stderr, flush=True)
            summary["inputs"] += 1
            try:
                read(target)
                summary["accepted"] += 1
            except InputError as exc:
                summary["refused"] += 1
                if "\n" in str(exc):
                    summary["escapes"].append([name, kind, k, "InputError of several lines", str(exc)[:200]])
            except BaseException as exc:  # noqa: BLE001  -- any other escape is what this counts
                where = traceback.extract_tb(exc.__traceback__)[-1]
                summary["escapes"].append([name, kind, k, type(exc).__name__, f"{str(exc)[:160]} "
                                           f"({Path(where.filename).name}:{where.lineno})"])
    return summary


if __name__ == "__main__":
    from engine.base.versions import code_commit

    print(json.dumps({**run(Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])), "commit": code_commit()}))
