"""`train --background random` (engine.train.trainer.Trainer._on_random_background): where the Gaussians leave a
training view uncovered, the loss sees a colour drawn anew for each view, so a dark photo is matched by opaque
Gaussians and not by seeing through to black (the skull capture's model had a median opacity of 0)."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import pytest
import torch

from engine.base.errors import InputError
from engine.render.rasterize import RenderOutput
from engine.train.config import TrainConfig
from engine.train.trainer import Trainer


def test_uncovered_pixels_show_a_colour_drawn_for_each_view_and_covered_ones_their_own():
    owner = SimpleNamespace(generator=torch.Generator().manual_seed(0))  # what the method reads of a trainer
    alpha = torch.tensor([[0.0, 1.0, 0.5]])
    out = RenderOutput(rgb=torch.full((1, 3, 3), 0.2), depth=None, alpha=alpha, identity=None, logits=None, info={})
    first, second = (Trainer._on_random_background(owner, out).rgb for _ in range(2))
    assert torch.allclose(first[0, 1], torch.full((3,), 0.2))  # opaque: its own colour
    drawn = first[0, 0] - 0.2  # transparent: its own (premultiplied) colour plus the drawn one
    assert torch.allclose(first[0, 2], 0.2 + 0.5 * drawn)
    assert not torch.allclose(first[0, 0], second[0, 0])  # a new colour each time


def test_an_unknown_background_is_refused():
    with pytest.raises(InputError, match="--background"):
        dataclasses.replace(TrainConfig(), background="white").resolved()
