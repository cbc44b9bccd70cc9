"""Ref-<inpainter>: one fill for the hole, placed in a reference view and carried to every view through depth,
then a new scene trained on it as Init does (engine.complete.reference_fill says how and why). The fill is the
median of every view's own fill carried into the reference (--consensus, the default), or the reference's own
(--no-consensus: Ref[single], the first version)."""

from __future__ import annotations

import json
from pathlib import Path

from engine.complete.methods.init import Init
from engine.complete.registry import Option, register

PLANE = Option("plane_texture", False, "ref: the hole's part on the support plane filled once in the plane's own "
               "texture and carried into every view by the plane (engine.complete.plane_texture)")
CONSENSUS = Option("consensus", True, "ref: the fill carried is the median of every view's own fill of each point "
                   "(off: the reference view's own fill)")


@register
class Reference(Init):
    name = "reference"
    label = "Ref"
    summary = "inpaint one reference view, carry its fill to every view by depth, train a new scene"
    options = (*Init.options, CONSENSUS, PLANE)
    cells = {"reference": {}, "reference-single": {"consensus": False},
             "reference-scratch": {"warm": False, "keep_rest": False}, "reference-plane": {"plane_texture": True}}

    def title(self, inpainter: str, options: dict) -> str:
        return (super().title(inpainter, options) + ("" if options.get("consensus", True) else "[single]")
                + ("[plane]" if options.get("plane_texture") else ""))

    def after_scene(self, job, scene_dir: Path) -> dict | None:
        from engine.complete.reference_fill import write_reference_fill
        from engine.formats.layout import SceneLayout
        from engine.inpaint.run import inpainted_dilation

        scene = job.original.scene
        report = write_reference_fill(SceneLayout(scene_dir), scene.cameras, scene.train, job.holes, job.inpainted,
                                      inpainted_dilation(job.inpainted), job.options["consensus"],
                                      plane_fill(job) if job.options.get("plane_texture") else None)
        (Path(scene_dir) / "reference_fill.json").write_text(json.dumps(report, indent=1))
        return super().after_scene(job, scene_dir)


def plane_fill(job):
    """The support plane and footprint `remove` found, with the inpainting's inpainter; None without a plane
    (the texture then stays out and Ref carries its fill alone)."""
    from engine.complete.reference_fill import PlaneFill
    from engine.edit.support_plane import removal_footprint, removal_plane
    from engine.inpaint.run import inpainted_inpainter

    plane, footprint = removal_plane(job.removed), removal_footprint(job.removed)
    if plane is None or footprint is None:
        return None
    return PlaneFill(plane, footprint, inpainted_inpainter(job.inpainted))
