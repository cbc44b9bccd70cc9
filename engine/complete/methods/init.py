"""Init-<inpainter> (the paper's re-initialisation): a new scene trained on the inpainted views, from the removed
scene's Gaussians by default (Init-<inpainter>[warm]; --no-warm: from scratch, kept to the hole unless
--no-keep-rest trains the paper's whole new scene; engine.complete.retrain).

The training images are the inpainted render inside the removed object's region (removal's masks grown by
the inpainting's dilation and 2 px), inside the holes as inpainted (`holes` takes in the band around a hole that
the photos contradict, which reaches past the region) and inside its shadow where `remove` relit one
(removed/effects, grown by 2 px: the input images still show it), and the input image elsewhere; original
cameras and sparse points, the removed object's id turned into background. Why not the renders alone: outside
the region the input image is the truth, and a render of the removed scene is only a copy of it with the model's
errors, which a new scene would learn. (Measured on a tiny run, test-view PSNR: 16.0 dB on renders alone, 16.4 with the
input images, against 20.0 for the unfilled scene; most of that gap is the tiny runs' seed noise.)
"""

from __future__ import annotations

from engine.complete.registry import register
from engine.complete.retrain import NewSceneMethod

MARGIN_PX = 2  # beyond the inpainting's own dilation


@register
class Init(NewSceneMethod):
    name = "init"
    label = "Init"
    summary = "train a new scene from the inpainted views (the paper's Init)"
    cells = {"init": {}, "init-scratch": {"warm": False, "keep_rest": False},  # the paper's whole new scene
             "init-colmap": {"recolmap": True, "warm": False}}

    def keep_regions(self, job) -> dict:
        from engine.inpaint.run import inpainted_dilation
        from engine.io.masks import read_masks

        cameras = job.original.scene.cameras
        pixels = inpainted_dilation(job.inpainted) + MARGIN_PX
        regions = read_masks(job.removed.masks, cameras, pixels)
        if job.holes.root.is_dir():  # what the inpainter replaced, the holes' border band included
            holes = read_masks(job.holes.root, cameras, pixels)
            regions = {i: regions[i] | holes[i] for i in regions}
        effects = job.removed.effects.root  # the shadow, relit in the removed renders
        if not effects.is_dir():
            return regions
        relit = read_masks(effects, cameras, MARGIN_PX)
        return {i: regions[i] | relit[i] for i in regions}
