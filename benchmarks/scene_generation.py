"""How long the scene generator takes: scripts/make_scene.py for each family at one size, one after the other, the
wall time of the whole command (Cycles on the CPU, then the engine's build-scene) as one record.

    .venv-blender/bin/python benchmarks/scene_generation.py --out DIR [--views 24] [--res 256] [--samples 16]
        [--families livingroom statue tabletop] [--json OUT.json]

Blender's Python (the bpy module or `blender -b -P ... --`): it runs the generator with its own interpreter.
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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="a new folder for the scenes")
    parser.add_argument("--families", nargs="+", default=["livingroom", "statue", "tabletop"])
    parser.add_argument("--views", type=int, default=24)
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--gt", default="all")
    parser.add_argument("--json", help="also write the record here")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    from engine.base.versions import code_commit

    rows = []
    for family in args.families:
        start = time.perf_counter()
        subprocess.run([sys.executable, str(REPO / "scripts" / "make_scene.py"), "--family", family, "--out",
                        str(Path(args.out) / family), "--views", str(args.views), "--res", str(args.res),
                        "--samples", str(args.samples), "--gt", args.gt], check=True, stdout=subprocess.DEVNULL)
        rows.append({"family": family, "views": args.views, "width": args.res, "samples": args.samples,
                     "gt": args.gt, "wall_s": round(time.perf_counter() - start, 1)})
        print(json.dumps(rows[-1]), flush=True)
    record = {"scenes": rows, "cores": os.cpu_count(), "commit": code_commit(), "command": " ".join(sys.argv)}
    if args.json:
        Path(args.json).write_text(json.dumps(record, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
