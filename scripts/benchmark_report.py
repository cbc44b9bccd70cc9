"""The benchmark's stability report and speed-versus-accuracy chart, from its result cells.

Pure Python (no numpy, no OpenCV), because scripts/benchmark.py also runs in Blender's Python.
- stability.md: per scene and method, mean and spread (sample standard deviation) over seeds of PSNR and
  m-PSNR, how many seeds finished, and every failure with its reason.
- speed_accuracy.svg: run time (x, log scale) against m-PSNR and against PSNR (two panels), one labelled
  point per method, averaged over scenes and seeds. The same drawing items go to speed_accuracy.json,
  from which `python -m engine chart` draws speed_accuracy.png.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from statistics import mean, stdev

WIDTH, HEIGHT, MARGIN = 460, 340, 60


def _spread(values: list[float]) -> str:
    if not values:
        return "n/a"
    return f"{mean(values):.2f} ± {stdev(values):.2f}" if len(values) > 1 else f"{values[0]:.2f} (one seed)"


def stability_lines(cells: list[dict]) -> list[str]:
    lines = ["# Stability over seeds", "", "| Scene | Method | seeds done | PSNR | m-PSNR |", "|---|---|---|---|---|"]
    for scene, method in sorted({(c["scene"], c["method"]) for c in cells}):
        mine = [c for c in cells if c["scene"] == scene and c["method"] == method]
        done = [c for c in mine if c["status"] == "done"]
        lines.append(f"| {scene} | {method} | {len(done)}/{len(mine)} | "
                     f"{_spread([c['psnr'] for c in done if c.get('psnr') is not None])} | "
                     f"{_spread([c['m_psnr'] for c in done if c.get('m_psnr') is not None])} |")
    failed = [c for c in cells if c["status"] == "failed"]
    lines += ["", "## Failures", ""]
    lines += [f"- {c['scene']} seed {c['seed']} {c['method']}: {c['reason']}" for c in failed] or ["none"]
    return lines + [""]


def _points(cells: list[dict], key: str) -> list[tuple[str, float, float]]:
    done = [c for c in cells if c["status"] == "done" and c.get(key) is not None and c.get("seconds")]
    return [(m, mean(c["seconds"] for c in done if c["method"] == m), mean(c[key] for c in done if c["method"] == m))
            for m in sorted({c["method"] for c in done})]


def _panel(points: list[tuple[str, float, float]], label: str, left: int) -> list[list]:
    """One panel as drawing items: ["line", x1, y1, x2, y2], ["dot", x, y], ["text", x, y, text, anchor]."""
    if not points:
        return []
    xs = [math.log10(max(p[1], 1e-3)) for p in points]
    ys = [p[2] for p in points]
    x0, x1 = min(xs) - 0.1, max(xs) + 0.1
    y0, y1 = min(ys) - 0.5, max(ys) + 0.5

    def at(x: float, y: float) -> tuple[float, float]:
        return (left + MARGIN + (x - x0) / (x1 - x0) * (WIDTH - 2 * MARGIN),
                HEIGHT - MARGIN - (y - y0) / (y1 - y0) * (HEIGHT - 2 * MARGIN))

    ox, oy, right = left + MARGIN, HEIGHT - MARGIN, left + WIDTH - MARGIN
    items = [["line", ox, oy, right, oy], ["line", ox, oy, ox, MARGIN],
             ["text", left + WIDTH / 2, HEIGHT - 15, "run time (s, log scale)", "middle"],
             ["text", ox, MARGIN - 14, label, "middle"],
             ["text", ox, oy + 18, f"{10 ** x0:.0f}", "middle"], ["text", right, oy + 18, f"{10 ** x1:.0f}", "middle"],
             ["text", ox - 6, oy, f"{y0:.1f}", "end"], ["text", ox - 6, MARGIN + 4, f"{y1:.1f}", "end"]]
    placed: list[tuple[float, float, float, float]] = []
    for (name, _, _), x, y in zip(points, xs, ys, strict=True):
        px, py = at(x, y)
        items += [["dot", px, py], _label(name, px, py, left + WIDTH, placed)]
    return items


def _label(name: str, px: float, py: float, right: float, placed: list) -> list:
    """A point's label beside it, moved up or down until it overlaps no label placed before (and to the
    point's left where it would leave the panel). Text width is estimated at 7 px per character."""
    width = 7 * len(name)
    start = px + 8 if px + 8 + width < right else px - 8 - width
    for shift in (0, 15, -15, 30, -30, 45, -45, 60, -60):
        box = (start, py - 6 + shift - 12, start + width, py - 6 + shift)
        if not any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in placed):
            break
    placed.append(box)
    return ["text", start, box[3], name, "start"]


def speed_accuracy_chart(cells: list[dict]) -> dict:
    """The chart as a list of drawing items: written as SVG here, and as PNG by the engine (`engine chart`),
    which has OpenCV; Blender's Python has neither a PNG rasterizer nor fonts."""
    items = _panel(_points(cells, "m_psnr"), "m-PSNR (dB)", 0) + _panel(_points(cells, "psnr"), "PSNR (dB)", WIDTH)
    return {"width": 2 * WIDTH, "height": HEIGHT, "items": items}


def chart_svg(chart: dict) -> str:
    anchors = {"start": "start", "middle": "middle", "end": "end"}
    body = []
    for kind, *v in chart["items"]:
        if kind == "line":
            body.append(f'<line x1="{v[0]:.1f}" y1="{v[1]:.1f}" x2="{v[2]:.1f}" y2="{v[3]:.1f}" stroke="black"/>')
        elif kind == "dot":
            body.append(f'<circle cx="{v[0]:.1f}" cy="{v[1]:.1f}" r="5" fill="#1f77b4"/>')
        else:
            body.append(f'<text x="{v[0]:.1f}" y="{v[1]:.1f}" text-anchor="{anchors[v[3]]}">{v[2]}</text>')
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{chart["width"]}" height="{chart["height"]}" '
            f'font-family="sans-serif" font-size="13"><rect width="100%" height="100%" fill="white"/>'
            + "".join(body) + "</svg>\n")


def write_reports(cells: list[dict], out: Path) -> Path:
    """stability.md, speed_accuracy.svg and the chart's items (speed_accuracy.json, for the PNG)."""
    (out / "stability.md").write_text("\n".join(stability_lines(cells)))
    chart = speed_accuracy_chart(cells)
    (out / "speed_accuracy.svg").write_text(chart_svg(chart))
    (out / "speed_accuracy.json").write_text(json.dumps(chart))
    return out / "speed_accuracy.json"
