"""What the methods that train a new scene share (Init and Direct): the paper's COLMAP ablation as an option.

--recolmap: the training scene's poses and sparse points are re-estimated by COLMAP from its training
images (engine.complete.recolmap), and the report gives how many views registered and their pose error
against the original cameras. Torch-free at the top, like every plug-in (engine.complete.registry).
"""

from __future__ import annotations

from pathlib import Path

from engine.base.plugins import Needs
from engine.complete.registry import CompletionMethod, Option

RECOLMAP = Option("recolmap", False, "re-estimate poses and points from the inpainted images with pycolmap "
                  "(the paper's COLMAP ablation; init and direct)")


class NewSceneMethod(CompletionMethod):
    """Trains a new Gaussian Grouping scene from scratch on the inpainted views, with the original run's
    settings and step count (the base class's setup)."""

    options = (RECOLMAP,)
    needs = Needs(packages=("pycolmap (with --recolmap)",))

    def title(self, inpainter: str, options: dict) -> str:
        return super().title(inpainter, options) + ("[colmap]" if options.get("recolmap") else "")

    def after_scene(self, job, scene_dir: Path) -> dict | None:
        if not job.options.get("recolmap"):
            return None
        from engine.complete.recolmap import rerun_colmap

        scene = job.original.scene
        return rerun_colmap(scene_dir, [scene.names[i] for i in scene.train], scene_dir / "colmap")
