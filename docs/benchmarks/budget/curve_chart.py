"""The budget curve as a picture: test PSNR against training time, and Init-exemplar's m-PSNR against its cell's
time, one dot per (scene, budget); run1's records, with the 300k points from effects/run13 (same scenes, four
trainings at once on the same kind of host).

    PYTHONPATH=. python3 docs/benchmarks/budget/curve_chart.py   # writes docs/benchmarks/budget/curve.png
"""

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(ROOT / "scripts"))
from benchmark_report import HEIGHT, WIDTH, _panel  # noqa: E402

from engine.io.image_io import write_png  # noqa: E402
from engine.pictures.chart_png import draw_chart  # noqa: E402

HERE = Path(__file__).resolve().parent
NAMES = {"50000": "50k", "100000": "100k", "1000000": "1M", "0": "none"}


def points() -> tuple[list, list]:
    train, init = [], []
    folders = [(p, NAMES[p.name.rsplit("_b", 1)[1]]) for p in sorted((HERE / "run1/records").iterdir())]
    folders += [(HERE.parent / "effects/run13/records" / s, "300k") for s in ("livingroom_s0", "statue_s0")]
    for folder, budget in folders:
        name = f"{folder.name[:3]} {budget}"
        metrics = json.loads((folder / "metrics.json").read_text())
        scores = json.loads((folder / "Init-exemplar_scores.json").read_text())
        stages = json.loads((folder / "stage_times.json").read_text())
        train.append((name, metrics["train_seconds"], metrics["psnr"]))
        init.append((name, sum(stages.values()) + scores["seconds"], scores["scores"]["m_psnr"]))
    return train, init


def main() -> None:
    train, init = points()
    items = _panel(train, "test PSNR (dB)", 0) + _panel(init, "Init-exemplar m-PSNR (dB)", WIDTH)
    out = HERE / "curve.png"
    write_png(out, draw_chart({"width": 2 * WIDTH, "height": HEIGHT, "items": items}))
    print(out)


if __name__ == "__main__":
    main()
