"""Rebuild a seed's results.json from its packed records (collect.sh's pack/<scene>/), when the device's
`--report-only` was asked for fewer cells than ran (run 3: collect_seeds.sh without METHODS, INPAINTERS and
PERCEPTUAL, so its results.json held only Init-exemplar and Ref-exemplar).

Each cell's record is built as scripts/benchmark_stages.run_cell builds it: the scores, Gaussians, config and
removed scene's scores from the cell's own scores.json; its run time the same sum (the shared stages from
stage_times.json, then the completion's seconds); the base run's, scene's and versions' settings from a record
of the same seed that the device did write (they are the same run's), the inpainting's with its inpainter.

    PYTHONPATH=. python docs/benchmarks/full/pack_records.py RUN3/seed0   (writes RUN3/seed0/results.json)
"""

import copy
import json
import sys
from pathlib import Path

from engine.complete.registry import get

root = Path(sys.argv[1])
template = json.loads((root / "results.json").read_text())
done = [c for c in template if c.get("status") == "done"]
cells = []
for scene_dir in sorted((root / "pack").iterdir()):
    times = json.loads((scene_dir / "stage_times.json").read_text())
    model = next(c for c in done if c["scene"] == scene_dir.name)
    for path in sorted(scene_dir.glob("*_scores.json")):
        report = json.loads(path.read_text())
        config, source = report["config"], get(report["config"]["method"]).source
        inpainter = config["inpainter"]
        shared = ([f"inpaint-direct-{inpainter}"] if source == "input"
                  else ["train", "remove", "holes", f"inpaint-{inpainter}"])
        settings = copy.deepcopy(model["settings"])
        settings["inpaint"].update(inpainter=inpainter, source=source)
        settings["complete"] = config
        cells.append({"scene": scene_dir.name, "seed": model["seed"], "inpainter": inpainter,
                      "method": report["method"], "status": "done", **report["scores"],
                      "gaussians": report["gaussians"], "settings": settings, "scene_dir": model["scene_dir"],
                      "renders": str(Path(config["out"]) / "renders"),
                      "seconds": round(sum(times.get(k, 0) for k in shared) + report["seconds"], 1),
                      "removed_scores": report["removed_scores"], "unavailable": report["unavailable"]})
# check against what the device wrote
for old in done:
    new = next(c for c in cells if c["method"] == old["method"] and c["scene"] == old["scene"])
    assert new == old, (old["method"], {k for k in old if old[k] != new.get(k)})
(root / "results.json").write_text(json.dumps(cells, indent=1))
print(f"{len(cells)} cells -> {root / 'results.json'}")
