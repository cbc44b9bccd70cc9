"""Join the records of benchmark runs made apart (each seed in its own device session) into one table:
tables.md with each column's mean over seeds, stability.md with the spread and the failure table, and the
chart, all from the records alone (nothing is run).

    PYTHONPATH=.:scripts python benchmarks/merge_tables.py OUT run1/results.json run2/results.json
    PYTHONPATH=. python -m engine chart --spec OUT/speed_accuracy.json --out OUT/speed_accuracy.png

`PATH:SCENE` takes only that scene's cells from a file. Records of more than one commit are refused unless
--mixed-commits is given first; each method is then named with its commit.
"""

import json
import sys
from pathlib import Path

from benchmark import MixedCommits, write_results

out = Path(sys.argv[1])
out.mkdir(parents=True, exist_ok=True)


def records(arg: str) -> list[dict]:
    path, _, scene = arg.partition(":")
    return [c for c in json.loads(Path(path).read_text()) if not scene or c["scene"] == scene]


mixed = "--mixed-commits" in sys.argv
cells = [cell for arg in sys.argv[2:] if arg != "--mixed-commits" for cell in records(arg)]
seen = {(c["scene"], c["seed"], c["method"]) for c in cells}
if len(seen) != len(cells):
    sys.exit("the records repeat a scene, seed and method: give each run's results.json once")
try:
    write_results(cells, out, mixed)
except MixedCommits as exc:
    sys.exit(str(exc))
print(f"{len(cells)} cells -> {out / 'tables.md'}, {out / 'stability.md'}")
