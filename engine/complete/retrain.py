"""What the methods that train a new scene share (Init and Direct): the paper's COLMAP ablation and a warm
start as options.

--recolmap: the training scene's poses and sparse points are re-estimated by COLMAP from its training
images (engine.complete.recolmap), and the report gives how many views registered and their pose error
against the original cameras.

--warm (the default; --no-warm is the paper's from-scratch variant): the new scene starts from what the base
run already knows instead of the sparse points: the removed scene's Gaussians (the base run without the object)
and the base run's identity classifier, and trains for a tenth of the base run's steps unless --steps says
otherwise. Only what renders into the hole trains (the removed scene's Gaussians there and new ones seeded on
the hole's inpainted surface); the rest is fixed, so outside the hole every view renders as the removed scene
does (engine.complete.warm_start, engine.complete.hole_region). The results name it (Init-<inpainter>[warm]). Why
the default: on the GPU (640x480/100 views, exemplar, one training a family), before the rest was fixed, it scored
higher m-SSIM in all six cells of livingroom and statue (Init, Ref, Direct), higher m-PSNR in five (+0.09 to
+0.56 dB; Ref on the statue -0.02), in 34-42 s less per cell. Torch-free at the top, like every plug-in
(engine.complete.registry).
"""

from __future__ import annotations

from pathlib import Path

from engine.base.errors import InputError
from engine.base.plugins import Needs
from engine.complete.registry import CompletionMethod, Option

RECOLMAP = Option("recolmap", False, "re-estimate poses and points from the inpainted images with pycolmap "
                  "(the paper's COLMAP ablation; init and direct)")
WARM = Option("warm", True, "start from the removed scene's Gaussians and the base run's classifier instead of "
              "the sparse points and train only what renders into the hole, the rest fixed, for a tenth of the base "
              "run's steps unless --steps is given; --no-warm trains from scratch as the paper does (init, direct, "
              "reference)")


KEEP_REST = Option("keep_rest", True, "with --no-warm: keep the removed scene outside the hole and take from the new "
                   "scene only what renders into the hole alone (off: the paper's whole new scene; --recolmap, whose "
                   "scene is in COLMAP's new frame, keeps it whole)")


def kept_whole(options: dict) -> bool:
    """Whether a from-scratch run keeps its whole new scene: --no-keep-rest, or --recolmap (its scene is in COLMAP's
    new frame); the title's [whole] and the graft both read it."""
    return not options.get("warm") and bool(options.get("recolmap") or not options.get("keep_rest", True))


class NewSceneMethod(CompletionMethod):
    """Trains a new Gaussian Grouping scene from scratch on the inpainted views, with the original run's
    settings and step count (the base class's setup)."""

    options = (RECOLMAP, WARM, KEEP_REST)
    needs = Needs(packages=("pycolmap (with --recolmap)",))

    def title(self, inpainter: str, options: dict) -> str:
        return (super().title(inpainter, options) + ("[colmap]" if options.get("recolmap") else "")
                + ("[warm]" if options.get("warm") else "") + ("[whole]" if kept_whole(options) else ""))

    def after_train(self, job) -> dict | None:
        """Warm: what trained kept to the hole (engine.complete.warm_start.confine). From scratch: the new scene
        grafted into the removed one at the hole (warm_start.graft) unless --no-keep-rest or --recolmap keeps it
        whole."""
        if kept_whole(job.options):
            return None
        if not job.holes.root.is_dir():  # Direct needs no hole masks, and without them the hole is unknown
            return {"kept_whole": f"{job.holes.root} missing: run `holes` to keep the rest as removal left it"}
        from engine.complete.warm_start import confine, graft

        return confine(job, warm=True) if job.options.get("warm") else graft(job)

    def check(self, job) -> None:
        if job.options.get("warm") and job.options.get("recolmap"):
            raise InputError("--warm (the default) starts from Gaussians in the original cameras' frame, which "
                             "--recolmap replaces: add --no-warm to re-estimate them")

    def setup(self, job, settings):
        if not job.options.get("warm"):
            return settings, None
        from engine.complete.warm_start import warm_setup

        return warm_setup(job, settings)

    def after_scene(self, job, scene_dir: Path) -> dict | None:
        if not job.options.get("recolmap"):
            return None
        from engine.complete.recolmap import rerun_colmap

        scene = job.original.scene
        return rerun_colmap(scene_dir, [scene.names[i] for i in scene.train], scene_dir / "colmap")
