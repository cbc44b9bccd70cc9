"""Per-view colour correction learned with the scene (`train --colour-correction`).

Why: a phone changes exposure and white balance from photo to photo, and a scene trained on such photos has
one colour per surface to give them all; it makes up the difference with view-dependent colour and floaters
that show from every other view. 3DGS trainers absorb it with a per-image correction (gsplat's trainer: per-image
appearance embeddings or a bilateral grid). Here each training view gets a 3x3 colour matrix and an offset,
applied to its render before the loss and learned with Adam; the scene itself renders without them (test
views, export, Blender). The corrections are kept centred, their mean the identity, so the scene's colours are
the photos' average and not a drifting one.
"""

from __future__ import annotations

import torch

from engine.train.adam_step import AdamState


class ViewColours:
    """One affine colour correction per training view, rgb -> rgb (I + M) ^T + b, starting at the identity."""

    def __init__(self, views: list[int], device: torch.device, lr: float) -> None:
        self.index = {view: k for k, view in enumerate(views)}
        self.matrix = torch.nn.Parameter(torch.zeros(len(views), 3, 3, device=device))
        self.offset = torch.nn.Parameter(torch.zeros(len(views), 3, device=device))
        self.optimizer = AdamState([self.matrix, self.offset], lr=lr, eps=1e-15, name="view_colours")
        self.eye = torch.eye(3, device=device)

    def __call__(self, view: int, rgb: torch.Tensor) -> torch.Tensor:
        """(H, W, 3) the render as view `view`'s photo shows the scene."""
        k = self.index[view]
        return rgb @ (self.eye + self.matrix[k]).T + self.offset[k]

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
        gains = torch.diagonal(self.matrix.detach(), dim1=1, dim2=2)
        return {"views": len(self.index), "max_gain_change": round(float(gains.abs().max()), 4),
                "max_offset": round(float(self.offset.detach().abs().max()), 4)}
