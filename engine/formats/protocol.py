"""Which generated scenes may tune a default and which only report: the benchmark's protocol.

Scene seeds 0-99 are tuning seeds: thresholds, rules and defaults may be chosen on them. Seeds from HELD_OUT_FROM
on are held out: only the published table runs them, so its numbers come from scenes no default was chosen on.
Every earlier number came from seed 0 of each family, the scenes the defaults were tuned on, and on a held-out
livingroom every completion scored below leaving the hole unfilled. The seed is the one scripts/make_scene.py
wrote into the scene's scene.json; a capture (no generator seed) is neither.
"""

from __future__ import annotations

import json
from pathlib import Path

from engine.base.errors import InputError
from engine.formats.layout import SceneLayout

HELD_OUT_FROM = 100  # scene seeds from here on only report


def scene_role(scene: Path | str) -> str | None:
    """"held-out", "tuning", or None for a scene no generator made (a capture)."""
    path = SceneLayout(scene).scene_json
    try:
        seed = json.loads(path.read_text()).get("seed") if path.is_file() else None
    except (OSError, ValueError):
        seed = None
    if not isinstance(seed, int):
        return None
    return "held-out" if seed >= HELD_OUT_FROM else "tuning"


def refuse_held_out(scene: Path | str, tool: str) -> None:
    """One line and no work when a tuning tool is pointed at a held-out scene."""
    if scene_role(scene) == "held-out":
        raise InputError(f"{scene} is a held-out scene (seed {HELD_OUT_FROM} or more): {tool} chooses settings, "
                         f"so run it on a tuning scene (make_scene.py --seed 0-{HELD_OUT_FROM - 1})")
