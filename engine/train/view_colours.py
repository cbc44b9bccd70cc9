"""Per-view colour correction learned with the scene (`train --colour-correction`).

Why: a phone changes exposure and white balance from photo to photo, and a scene trained on such photos has
one colour per surface to give them all; it makes up the difference with view-dependent colour and floaters
that show from every other view. 3DGS trainers absorb it with a per-image correction (gsplat's trainer: per-image
appearance embeddings or a bilateral grid). Here each training view gets a 3x3 colour matrix and an offset
(`affine`), or a gain per channel alone (`gain`: an exposure and white balance, nothing a scene's content could
hide in), applied to its render before the loss and learned with Adam; the scene itself renders without them (test
views, export, Blender). The corrections are kept centred, their mean the identity, so the scene's colours are
the photos' average and not a drifting one. Why `gain` too: on the shared skull capture the affine correction cost
2.9 dB of test PSNR (22.87 -> 19.94, H200) where it gave the statue +0.9 dB.
"""

from __future__ import annotations

import torch

from engine.train.adam_step import AdamState


class ViewColours:
    """One colour correction per training view, starting at the identity: `affine` rgb -> rgb (I + M) ^T + b,
    `gain` rgb -> rgb (1 + g), per channel."""

    def __init__(self, views: list[int], device: torch.device, lr: float, model: str = "affine") -> None:
        self.index, self.model = {view: k for k, view in enumerate(views)}, model
        self.matrix = torch.nn.Parameter(torch.zeros(len(views), *((3, 3) if model == "affine" else (3,)),
                                                     device=device))
        self.offset = torch.nn.Parameter(torch.zeros(len(views), 3, device=device))
        trained = [self.matrix, self.offset] if model == "affine" else [self.matrix]
        self.optimizer = AdamState(trained, lr=lr, eps=1e-15, name="view_colours")
        self.eye = torch.eye(3, device=device)

    def __call__(self, view: int, rgb: torch.Tensor) -> torch.Tensor:
        """(H, W, 3) the render as view `view`'s photo shows the scene."""
        k = self.index[view]
        if self.model == "gain":
            return rgb * (1.0 + self.matrix[k])
        return rgb @ (self.eye + self.matrix[k]).T + self.offset[k]

    def gains(self) -> torch.Tensor:
        """(views, 3) each view's gain per channel (an affine correction's diagonal)."""
        matrix = self.matrix.detach()
        return 1.0 + (matrix if self.model == "gain" else torch.diagonal(matrix, dim1=1, dim2=2))

    @torch.no_grad()
    def recentre(self) -> None:
        """Keep the mean correction the identity: the scene's own colours carry what all views share."""
        self.matrix -= self.matrix.mean(0, keepdim=True)
        self.offset -= self.offset.mean(0, keepdim=True)

    def state_dict(self) -> dict:
        return {"views": list(self.index), "matrix": self.matrix.detach().cpu(), "offset": self.offset.detach().cpu(),
                "optimizer": self.optimizer.state_dict()}

    def load_state_dict(self, state: dict) -> None:
        with torch.no_grad():
            self.matrix.copy_(state["matrix"])
            self.offset.copy_(state["offset"])
        self.optimizer.load_state_dict(state["optimizer"])

    def report(self) -> dict:
        """How far the views' corrections stray from the identity: the largest gain change and offset."""
        return {"views": len(self.index), "model": self.model,
                "max_gain_change": round(float((self.gains() - 1.0).abs().max()), 4),
                "max_offset": round(float(self.offset.detach().abs().max()), 4)}
