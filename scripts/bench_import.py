"""How long importing a 3DGS .ply into Blender as proxies takes (addon.import_scene.import_splats).

    .venv-blender/bin/python scripts/bench_import.py [--gaussians 1000000] [--groups 8]

Writes a .ply of that many Gaussians (degree-0 SH, identities one-hot over `groups` classes, with a matching
classifier.npz) to a temporary folder, imports it into an empty scene, and prints the time of reading
the file, of building the proxy objects, and of evaluating their geometry nodes once.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import bpy  # noqa: E402

from addon.import_scene import import_splats  # noqa: E402
from addon.splat_ply import read_splats  # noqa: E402


def write_ply(root: Path, n: int, groups: int) -> Path:
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1",
             "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"] + [f"obj_dc_{i}" for i in range(16)]
    rng = np.random.default_rng(0)
    data = np.zeros(n, dtype=[(name, "<f4") for name in names])
    for name in names:
        data[name] = rng.normal(size=n)
    label = rng.integers(0, groups, n)
    for i in range(16):
        data[f"obj_dc_{i}"] = (label == i) * 4.0
    header = f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\n"
    header += "".join(f"property float {name}\n" for name in names) + "end_header\n"
    (root / "point_cloud.ply").write_bytes(header.encode() + data.tobytes())
    weight = np.eye(groups, 16, dtype=np.float32)
    np.savez(root / "classifier.npz", weight=weight, bias=np.zeros(groups, np.float32))
    return root / "point_cloud.ply"


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--gaussians", type=int, default=1_000_000)
    parser.add_argument("--groups", type=int, default=8)
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    with tempfile.TemporaryDirectory() as tmp:
        ply = write_ply(Path(tmp), args.gaussians, args.groups)
        start = time.perf_counter()
        read_splats(ply)
        read = time.perf_counter() - start
        collection = bpy.data.collections.new("bench")
        bpy.context.scene.collection.children.link(collection)
        start = time.perf_counter()
        objects = import_splats(ply, collection)
        total = time.perf_counter() - start
        start = time.perf_counter()
        depsgraph = bpy.context.evaluated_depsgraph_get()
        instances = 0
        for o in objects:
            geometry = o.evaluated_get(depsgraph).evaluated_geometry()
            instances += len(geometry.instances_pointcloud().points)
        evaluate = time.perf_counter() - start
    print(f"{args.gaussians:,} Gaussians in {len(objects)} objects: read {read:.2f} s, import (read + build) "
          f"{total:.2f} s, geometry nodes {evaluate:.2f} s for {instances:,} instances")
    return 0


if __name__ == "__main__":
    sys.exit(main())
