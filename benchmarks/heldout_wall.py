"""The held-out run's wall time and throughput, from what its processes left: when the batch started (a file holding
the Unix time) and when each scene's matrix last wrote its results.json.

    python3 benchmarks/heldout_wall.py START_FILE HELDOUT_DIR [GPUS]     # prints JSON
"""

from __future__ import annotations

import json
import sys
from pathlib import Path


def main(start_file: str, folder: str, gpus: str = "") -> int:
    start = float(Path(start_file).read_text().split()[0])
    ends = {p.parent.name: p.stat().st_mtime for p in sorted(Path(folder).glob("*/results.json"))}
    wall = max(ends.values()) - start if ends else None
    record = {"gpus": int(gpus) if gpus else None, "scenes": len(ends), "wall_s": round(wall, 1) if wall else None,
              "scenes_per_hour": round(3600 * len(ends) / wall, 2) if wall else None,
              "per_scene_s": {name: round(end - start, 1) for name, end in ends.items()}}
    print(json.dumps(record, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
