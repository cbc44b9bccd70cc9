"""Ref-<inpainter>: the hole inpainted once, in one reference view, carried to every view through depth,
then a new scene trained on it as Init does (engine.complete.reference_fill says how and why)."""

from __future__ import annotations

import json
from pathlib import Path

from engine.complete.methods.init import Init
from engine.complete.registry import register


@register
class Reference(Init):
    name = "reference"
    label = "Ref"
    summary = "inpaint one reference view, carry its fill to every view by depth, train a new scene"
    cells = {"reference": {}}

    def after_scene(self, job, scene_dir: Path) -> dict | None:
        from engine.complete.reference_fill import write_reference_fill
        from engine.formats.layout import SceneLayout
        from engine.inpaint.run import inpainted_dilation

        scene = job.original.scene
        report = write_reference_fill(SceneLayout(scene_dir), scene.cameras, scene.train, job.holes, job.inpainted,
                                      inpainted_dilation(job.inpainted))
        (Path(scene_dir) / "reference_fill.json").write_text(json.dumps(report, indent=1))
        return super().after_scene(job, scene_dir)
