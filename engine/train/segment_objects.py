"""What `segment` (engine.segment) writes into RUN/segments/, as every later stage reads it back: the objects
found, and identities one-hot over them with the classifier that reads them."""

from __future__ import annotations

import numpy as np
import torch

from engine.base.errors import InputError
from engine.capture.scene import SceneObject
from engine.formats.checks import read_json
from engine.formats.splat_ply import IDENTITY_DIM

SHARPNESS = 20.0  # classifier logit for a Gaussian's own object: softmax ~1, so removal's threshold holds


def identity_of(ids: np.ndarray, count: int) -> tuple[torch.Tensor, torch.nn.Linear]:
    """Identities one-hot over the objects and the classifier that reads them (engine.train.trained_run)."""
    identity = torch.zeros(len(ids), IDENTITY_DIM)
    identity[torch.arange(len(ids)), torch.as_tensor(ids)] = 1.0
    classifier = torch.nn.Linear(IDENTITY_DIM, count + 1)
    with torch.no_grad():
        classifier.weight.copy_(SHARPNESS * torch.eye(count + 1, IDENTITY_DIM))
        classifier.bias.zero_()
    return identity, classifier


def read_segment_objects(layout) -> list[SceneObject]:
    """The objects of RUN/segments/objects.json (engine.formats.layout.RunLayout `layout`)."""
    path = layout.segments.objects_json
    try:
        return [SceneObject(int(e["id"]), str(e["name"]), bool(e.get("target", False)))
                for e in read_json(path)]
    except (OSError, ValueError, TypeError, KeyError, OverflowError) as exc:
        raise InputError(f"cannot read {path} ({exc}); delete {layout.segments.root} and run "
                         "`python -m engine segment` again") from exc
