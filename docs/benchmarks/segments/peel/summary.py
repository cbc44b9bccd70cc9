"""One line per scripts/bench_segments.py record in each folder given (named by the folder: before, today).

    python docs/benchmarks/segments/peel/summary.py DIR [DIR ...]
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[4]))
from scripts.bench_records import load_records  # noqa: E402

for folder in map(Path, sys.argv[1:]):
    for r in load_records(folder):
        a, m = r["auto"], r["masks"]
        print(folder.name, r["scene"], r["gaussians"], "proposals", a["proposals"], "target", a["target_iou"],
              "merges", a["merges"], a["objects"], "| masks", m["association"], m["target_iou"], flush=True)
