"""The benchmark's stability report and speed-versus-accuracy chart, from its result cells.

Pure Python (no numpy, no OpenCV), because benchmarks/matrix.py also runs in Blender's Python.
- stability.md: per scene and method, mean and spread (sample standard deviation) over seeds of PSNR and
  m-PSNR, how many seeds finished, and a failure table: crashes and out of memory with their reason, and
  cells that made the hole worse than the unfilled scene.
- speed_accuracy.svg: run time (x, log scale) against m-PSNR and against PSNR (two panels), one numbered
  point per method averaged over seeds (the numbers named in a legend), and the unfilled scene as a line:
  one row of panels per scene and, with several scenes, a last row averaged over them. The same drawing
  items go to speed_accuracy.json, from which `python -m engine chart` draws speed_accuracy.png.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from statistics import mean, stdev

WIDTH, HEIGHT, MARGIN = 460, 340, 60
LEGEND_COLUMNS, LEGEND_LINE = 3, 18


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
    rows = [_failure(c) for c in sorted(cells, key=lambda c: (c["scene"], c["seed"], c["method"]))]
    rows = [r for r in rows if r]
    lines += ["", "## Failures", "", "Crashes, out of memory, and finished cells whose m-PSNR is below the unfilled "
              "scene's (the fill made the hole worse than leaving it empty).", ""]
    if rows:
        lines += ["| Scene | Seed | Method | Failure | Detail |", "|---|---|---|---|---|", *rows]
    return lines + (["none", ""] if not rows else [""])


def _failure(cell: dict) -> str:
    """The cell's row in the failure table, or '' when it did not fail."""
    where = f"| {cell['scene']} | {cell['seed']} | {cell['method']} |"
    if cell["status"] == "failed":
        reason = cell.get("reason", "")
        kind = "out of memory" if "out of memory" in reason.lower() else "crash"
        return f"{where} {kind} | {reason.replace('|', '/')} |"
    unfilled = (cell.get("removed_scores") or {}).get("m_psnr")
    if cell["status"] == "done" and unfilled is not None and cell.get("m_psnr") is not None \
            and cell["m_psnr"] < unfilled:
        return f"{where} worse than unfilled | m-PSNR {cell['m_psnr']:.2f} against {unfilled:.2f} dB |"
    return ""


def _points(cells: list[dict], key: str) -> list[tuple[str, float, float]]:
    done = [c for c in cells if c["status"] == "done" and c.get(key) is not None and c.get("seconds")]
    return [(m, mean(c["seconds"] for c in done if c["method"] == m), mean(c[key] for c in done if c["method"] == m))
            for m in sorted({c["method"] for c in done})]


def _unfilled(cells: list[dict], key: str) -> float | None:
    """The unfilled scene's `key`, averaged over the scenes and seeds of `cells` (each counted once)."""
    values = {(c["scene"], c["seed"]): (c.get("removed_scores") or {}).get(key) for c in cells}
    values = [v for v in values.values() if v is not None]
    return mean(values) if values else None


def _panel(points: list[tuple[str, float, float]], label: str, left: int, top: int = 0,
           unfilled: float | None = None) -> list[list]:
    """One panel as drawing items: ["line", x1, y1, x2, y2], ["dot", x, y], ["text", x, y, text, anchor]."""
    if not points:
        return []
    items = _panel_at_top(points, label, left, unfilled)
    return [[kind, *_moved(kind, values, top)] for kind, *values in items]


def _moved(kind: str, values: list, top: int) -> list:
    """An item's coordinates moved `top` px down (lines have two points, dots and text one)."""
    if kind == "line":
        return [values[0], values[1] + top, values[2], values[3] + top]
    return [values[0], values[1] + top, *values[2:]]


def _panel_at_top(points: list[tuple[str, float, float]], label: str, left: int,
                  unfilled: float | None) -> list[list]:
    xs = [math.log10(max(p[1], 1e-3)) for p in points]
    ys = [p[2] for p in points]
    x0, x1 = min(xs) - 0.1, max(xs) + 0.1
    reach = ys + ([unfilled] if unfilled is not None else [])  # the unfilled line stays inside the panel
    y0, y1 = min(reach) - 0.5, max(reach) + 0.5

    def at(x: float, y: float) -> tuple[float, float]:
        return (left + MARGIN + (x - x0) / (x1 - x0) * (WIDTH - 2 * MARGIN),
                HEIGHT - MARGIN - (y - y0) / (y1 - y0) * (HEIGHT - 2 * MARGIN))

    ox, oy, right = left + MARGIN, HEIGHT - MARGIN, left + WIDTH - MARGIN
    items = [["line", ox, oy, right, oy], ["line", ox, oy, ox, MARGIN],
             ["text", left + WIDTH / 2, HEIGHT - 15, "run time (s, log scale)", "middle"],
             ["text", left + 10, MARGIN - 14, label, "start"],
             ["text", ox, oy + 18, f"{10 ** x0:.0f}", "middle"], ["text", right, oy + 18, f"{10 ** x1:.0f}", "middle"],
             ["text", ox - 6, oy, f"{y0:.1f}", "end"], ["text", ox - 6, MARGIN + 4, f"{y1:.1f}", "end"]]
    dots = [at(x, y) for x, y in zip(xs, ys, strict=True)]
    placed = [(px - 6, py - 6, px + 6, py + 6) for px, py in dots]  # labels keep off every dot too
    if unfilled is not None:  # the scene left with its hole: a fill below this line made it worse
        by = at(x0, unfilled)[1]
        items += [["line", ox, by, right, by], ["text", right, by - 4, "unfilled", "end"]]
        placed.append((right - 7 * 8, by - 16, right, by))
    for (name, _, _), (px, py) in zip(points, dots, strict=True):
        items += [["dot", px, py], *_label(name, px, py, left + WIDTH, placed)]
    return items


def _label(name: str, px: float, py: float, right: float, placed: list) -> list[list]:
    """A point's label beside it, moved up or down until it overlaps no dot or label placed before (and to the
    point's left where it would leave the panel), with a line back to its dot when moved. Text width is
    estimated at 7 px per character."""
    width = 7 * len(name)
    start = px + 8 if px + 8 + width < right else px - 8 - width
    for shift in (0, 15, -15, 30, -30, 45, -45, 60, -60):
        box = (start, py - 6 + shift - 12, start + width, py - 6 + shift)
        if not any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in placed):
            break
    placed.append(box)
    text = ["text", start, box[3], name, "start"]
    if shift == 0:
        return [text]
    end = box[0] if start > px else box[2]
    return [["line", px, py, end, box[3] - 6], text]


def speed_accuracy_chart(cells: list[dict]) -> dict:
    """The chart as a list of drawing items: written as SVG here, and as PNG by the engine (`engine chart`),
    which has OpenCV; Blender's Python has neither a PNG rasterizer nor fonts. Each method's points carry its
    number, named in a legend under the panels: method names are long, and a dozen of them crowd one corner."""
    scenes = sorted({c["scene"] for c in cells})
    rows = [(scene, [c for c in cells if c["scene"] == scene]) for scene in scenes]
    if len(rows) > 1:  # every method of every family, then their mean
        rows.append(("mean over scenes", cells))
    methods = sorted({c["method"] for c in cells if c["status"] == "done"})
    number = {m: str(k + 1) for k, m in enumerate(methods)}
    items = []
    for r, (name, mine) in enumerate(rows):
        for key, title, left in (("m_psnr", "m-PSNR (dB)", 0), ("psnr", "PSNR (dB)", WIDTH)):
            points = [(number[m], x, y) for m, x, y in _points(mine, key)]
            items += _panel(points, f"{name}: {title}", left, r * HEIGHT, _unfilled(mine, key))
    top = HEIGHT * max(len(rows), 1)
    per_row = (len(methods) + LEGEND_COLUMNS - 1) // LEGEND_COLUMNS
    for k, method in enumerate(methods):
        column, line = divmod(k, per_row)
        items.append(["text", MARGIN + column * (2 * WIDTH - MARGIN) / LEGEND_COLUMNS, top + 20 + line * LEGEND_LINE,
                      f"{number[method]}  {method}", "start"])
    height = top + (per_row * LEGEND_LINE + 20 if methods else 0)
    return {"width": 2 * WIDTH, "height": height, "items": items}


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
