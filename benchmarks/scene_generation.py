"""Generated scenes made and timed: scripts/make_scene.py for each family and scene seed, one after the other, the
wall time of each whole command (Cycles on the CPU, then the engine's build-scene) in one record. The held-out
table's scenes are

    .venv-blender/bin/python benchmarks/scene_generation.py --out DIR --preset benchmark \\
        --families tabletop statue livingroom wallmount --seeds 100 101 --json DIR/scene_generation.json

Scenes land in DIR/<family>_s<seed>. A size flag given (--views, --res, --samples, --gt, --extra-test) wins over the
preset's. Blender's Python (the bpy module or `blender -b -P ... --`): it runs the generator with its own
interpreter.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
SIZES = ("views", "res", "samples", "gt", "extra_test")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="a folder for the scenes (each a new folder in it)")
    parser.add_argument("--families", nargs="+", default=["livingroom", "statue", "tabletop"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[0], help="scene seeds (100 and up: held out)")
    parser.add_argument("--preset", default="default", help="make_scene.py's sizes by name")
    parser.add_argument("--views", type=int)
    parser.add_argument("--res", type=int)
    parser.add_argument("--samples", type=int)
    parser.add_argument("--gt")
    parser.add_argument("--extra-test", type=int)
    parser.add_argument("--json", help="also write the record here")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    from engine.base.versions import code_commit
    from engine.formats.layout import SceneLayout

    given = [k for k in SIZES if getattr(args, k) is not None]
    sizes = [f for k in given for f in (f"--{k.replace('_', '-')}", str(getattr(args, k)))]
    rows = []
    for family in args.families:
        for seed in args.seeds:
            out = Path(args.out) / f"{family}_s{seed}"
            start = time.perf_counter()
            subprocess.run([sys.executable, str(REPO / "scripts" / "make_scene.py"), "--family", family, "--out",
                            str(out), "--seed", str(seed), "--preset", args.preset, *sizes], check=True,
                           stdout=subprocess.DEVNULL)
            meta = json.loads(SceneLayout(out).scene_json.read_text())
            rows.append({"scene": out.name, **{k: meta.get(k) for k in ("family", "seed", *SIZES)},
                         "wall_s": round(time.perf_counter() - start, 1)})
            print(json.dumps(rows[-1]), flush=True)
    record = {"scenes": rows, "total_s": round(sum(r["wall_s"] for r in rows), 1), "cores": os.cpu_count(),
              "commit": code_commit(), "command": " ".join(sys.argv)}
    if args.json:
        Path(args.json).write_text(json.dumps(record, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
