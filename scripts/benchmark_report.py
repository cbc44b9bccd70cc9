"""The benchmark's stability report and speed-versus-accuracy chart, from its result cells.

Pure Python (no numpy, no OpenCV), because scripts/benchmark.py also runs in Blender's Python.
- stability.md: per scene and method, mean and spread (sample standard deviation) over seeds of PSNR and
  m-PSNR, how many seeds finished, and every failure with its reason.
- speed_accuracy.svg: run time (x, log scale) against m-PSNR and against PSNR (two panels), one labelled
  point per method, averaged over scenes and seeds.
"""

from __future__ import annotations

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


def _panel(points: list[tuple[str, float, float]], label: str, left: int) -> list[str]:
    if not points:
        return []
    xs = [math.log10(max(p[1], 1e-3)) for p in points]
    ys = [p[2] for p in points]
    x0, x1 = min(xs) - 0.1, max(xs) + 0.1
    y0, y1 = min(ys) - 0.5, max(ys) + 0.5

    def at(x: float, y: float) -> tuple[float, float]:
        return (left + MARGIN + (x - x0) / (x1 - x0) * (WIDTH - 2 * MARGIN),
                HEIGHT - MARGIN - (y - y0) / (y1 - y0) * (HEIGHT - 2 * MARGIN))

    ox, oy = left + MARGIN, HEIGHT - MARGIN
    out = [f'<line x1="{ox}" y1="{oy}" x2="{left + WIDTH - MARGIN}" y2="{oy}" stroke="black"/>',
           f'<line x1="{ox}" y1="{oy}" x2="{ox}" y2="{MARGIN}" stroke="black"/>',
           f'<text x="{left + WIDTH / 2}" y="{HEIGHT - 15}" text-anchor="middle">run time (s, log scale)</text>',
           f'<text x="{left + 15}" y="{HEIGHT / 2}" transform="rotate(-90 {left + 15} {HEIGHT / 2})" '
           f'text-anchor="middle">{label}</text>',
           f'<text x="{ox}" y="{oy + 18}" text-anchor="middle">{10 ** x0:.0f}</text>',
           f'<text x="{left + WIDTH - MARGIN}" y="{oy + 18}" text-anchor="middle">{10 ** x1:.0f}</text>',
           f'<text x="{ox - 6}" y="{oy}" text-anchor="end">{y0:.1f}</text>',
           f'<text x="{ox - 6}" y="{MARGIN + 4}" text-anchor="end">{y1:.1f}</text>']
    for (name, _, _), x, y in zip(points, xs, ys, strict=True):
        px, py = at(x, y)
        out += [f'<circle cx="{px:.1f}" cy="{py:.1f}" r="5" fill="#1f77b4"/>',
                f'<text x="{px + 8:.1f}" y="{py - 6:.1f}" font-size="12">{name}</text>']
    return out


def speed_accuracy_svg(cells: list[dict]) -> str:
    body = _panel(_points(cells, "m_psnr"), "m-PSNR (dB)", 0) + _panel(_points(cells, "psnr"), "PSNR (dB)", WIDTH)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * WIDTH}" height="{HEIGHT}" '
            f'font-family="sans-serif" font-size="13"><rect width="100%" height="100%" fill="white"/>'
            + "".join(body) + "</svg>\n")


def write_reports(cells: list[dict], out: Path) -> None:
    (out / "stability.md").write_text("\n".join(stability_lines(cells)))
    (out / "speed_accuracy.svg").write_text(speed_accuracy_svg(cells))
