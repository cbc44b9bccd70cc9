"""Draw a chart given as drawing items (scripts/benchmark_report.py makes them) into a PNG.

Why items and not a chart library: the benchmark runs in Blender's Python too, which has no plotting
library, no PNG rasterizer and no fonts; it lays the chart out once as items and writes the SVG itself,
and the engine, which has OpenCV, draws the same items as pixels. Items: ["line", x1, y1, x2, y2],
["dot", x, y], ["text", x, y, text, anchor] with anchor start | middle | end, in pixels of a chart
`width` x `height`.
"""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.io.image_io import write_png

SCALE = 2  # drawn at twice the layout's size, so text stays legible
FONT, FONT_SCALE = cv2.FONT_HERSHEY_SIMPLEX, 0.45 * SCALE
BLUE = (31, 119, 180)


def draw_chart(chart: dict) -> np.ndarray:
    """The chart as an RGB uint8 image."""
    try:
        width, height, items = int(chart["width"]), int(chart["height"]), chart["items"]
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"not a chart (needs width, height, items): {exc}") from exc
    image = np.full((height * SCALE, width * SCALE, 3), 255, np.uint8)

    def at(x: float, y: float) -> tuple[int, int]:
        return round(x * SCALE), round(y * SCALE)

    for kind, *v in items:
        if kind == "line":
            cv2.line(image, at(v[0], v[1]), at(v[2], v[3]), (0, 0, 0), SCALE, cv2.LINE_AA)
        elif kind == "dot":
            cv2.circle(image, at(v[0], v[1]), 5 * SCALE, BLUE, -1, cv2.LINE_AA)
        elif kind == "text":
            text, anchor = str(v[2]), v[3]
            (w, _), _ = cv2.getTextSize(text, FONT, FONT_SCALE, 1)
            x, y = at(v[0], v[1])
            x -= {"start": 0, "middle": w // 2, "end": w}[anchor]
            cv2.putText(image, text, (x, y), FONT, FONT_SCALE, (0, 0, 0), 1, cv2.LINE_AA)
        else:
            raise InputError(f"unknown chart item {kind!r}")
    return image


def chart_png(spec: Path, out: Path) -> Path:
    if not spec.is_file():
        raise InputError(f"{spec} missing: scripts/benchmark.py writes it beside speed_accuracy.svg")
    write_png(out, draw_chart(json.loads(spec.read_text())))
    return out
