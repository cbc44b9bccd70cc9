"""Join the records of benchmark runs made apart (on different machines, or one seed at a time) into one table:
tables.md with each column's mean over seeds, stability.md with the spread and the failure table, and the
chart, all from the records alone (nothing is run).

    python benchmarks/merge_tables.py OUT run1/results.json run2/results.json
    python -m engine chart --spec OUT/speed_accuracy.json --out OUT/speed_accuracy.png

`PATH:SCENE` takes only that scene's cells from a file. Records of more than one commit are refused unless
--mixed-commits is given first; each method is then named with its commit.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from benchmarks.matrix import MixedCommits, write_results  # noqa: E402


def records(arg: str) -> list[dict]:
    path, _, scene = arg.partition(":")
    return [c for c in json.loads(Path(path).read_text()) if not scene or c["scene"] == scene]


def main(argv: list[str]) -> int:
    if len(argv) < 2:
        sys.exit("usage: python benchmarks/merge_tables.py OUT [--mixed-commits] RESULTS.json[:SCENE]...")
    out = Path(argv[0])
    mixed = "--mixed-commits" in argv
    cells = [cell for arg in argv[1:] if arg != "--mixed-commits" for cell in records(arg)]
    if len({(c["scene"], c["seed"], c["method"]) for c in cells}) != len(cells):
        sys.exit("the records repeat a scene, seed and method: give each run's results.json once")
    out.mkdir(parents=True, exist_ok=True)
    try:
        write_results(cells, out, mixed)
    except MixedCommits as exc:
        sys.exit(str(exc))
    print(f"{len(cells)} cells -> {out / 'tables.md'}, {out / 'stability.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
