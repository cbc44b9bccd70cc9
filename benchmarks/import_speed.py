"""How long importing a 3DGS .ply into Blender as proxies takes (addon.import_scene.import_splats).

    .venv-blender/bin/python benchmarks/import_speed.py [--gaussians 1000000] [--groups 8] [--json OUT.json]

Writes a .ply of that many Gaussians (degree-0 SH, identities one-hot over `groups` classes, with a matching
classifier.npz) to a temporary folder, imports it into an empty scene, and prints the time of reading
the file, of building the proxy objects, and of evaluating their geometry nodes once; --json also writes them as a
record with the code's commit and the command.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import bpy  # noqa: E402

from addon.formats import layout, splat_ply  # noqa: E402
from addon.import_scene import import_splats  # noqa: E402
from addon.splat_ply import read_splats  # noqa: E402


def write_ply(root: Path, n: int, groups: int) -> Path:
    rng = np.random.default_rng(0)
    columns = {name: rng.normal(size=n) for name in splat_ply.property_names(0, with_identity=True)}
    label = rng.integers(0, groups, n)
    for i in range(splat_ply.IDENTITY_DIM):
        columns[f"obj_dc_{i}"] = (label == i) * 4.0
    run = layout.RunLayout(root)
    splat_ply.write_vertices(run.point_cloud, columns)
    splat_ply.write_classifier(run.classifier, np.eye(groups, splat_ply.IDENTITY_DIM, dtype=np.float32),
                               np.zeros(groups, np.float32))
    return run.point_cloud


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--gaussians", type=int, default=1_000_000)
    parser.add_argument("--groups", type=int, default=8)
    parser.add_argument("--json", help="also write the timings here as a record")
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
    if args.json:
        from engine.base.versions import code_commit

        record = {"gaussians": args.gaussians, "objects": len(objects), "read_s": round(read, 3),
                  "import_s": round(total, 3), "geometry_nodes_s": round(evaluate, 3), "instances": instances,
                  "blender": bpy.app.version_string, "commit": code_commit(), "command": " ".join(sys.argv)}
        Path(args.json).write_text(json.dumps(record, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
