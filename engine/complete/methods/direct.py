"""Direct-<inpainter> (the paper's Init-NanoBanana, made general): the object's whole region inpainted in
the input images (`inpaint --source input`), then the same training as Init on those images: by default from the
removed scene's Gaussians (Direct-<inpainter>[warm], so the removal's scene is its start); --no-warm trains from
scratch, the paper's baseline with no removal step in between."""

from __future__ import annotations

from engine.complete.registry import register
from engine.complete.retrain import NewSceneMethod


@register
class Direct(NewSceneMethod):
    name = "direct"
    label = "Direct"
    summary = "train a new scene on input images with the object painted out (the paper's direct baseline)"
    source = "input"
    cells = {"direct": {}, "direct-scratch": {"warm": False, "keep_rest": False}}
