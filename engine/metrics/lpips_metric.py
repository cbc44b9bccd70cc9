"""LPIPS (v0.1, AlexNet) from weights on disk, with the per-pixel map the masked metric needs.

The same network as the `lpips` package (Zhang et al. 2018): torchvision's AlexNet features up to conv5,
each of the five ReLU outputs unit-normalised over channels, squared differences weighted by a learned
1x1 convolution per layer, averaged over space and summed over layers. Inputs are scaled as lpips'
ScalingLayer does. The map (`lpips_map`) upsamples each layer's weighted difference bilinearly to the image
size before summing, as lpips(spatial=True) does; m-LPIPS is its mean over the hole.

Written here rather than imported because `lpips` imports torchvision, which the CPU torch build cannot
load; benchmarks/metrics_agreement.py compares the two on the GPU machine. Weights, nothing downloaded:
- backbone: torchvision's `alexnet-owt-7be5be79.pth`, from the `backbone` argument, LPIPS_BACKBONE, or
  torch's hub cache ($TORCH_HOME/hub/checkpoints/), where torchvision keeps it for users who have it;
- linear heads: `alex.pth` (6 kB) from the installed lpips package (found without importing it), or
  the `heads` argument.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import torch
import torch.nn.functional as F
from torch import nn

from engine.base.errors import InputError
from engine.base.weight_files import find_weights

BACKBONE_FILE = "alexnet-owt-7be5be79.pth"
CHANNELS = (64, 192, 384, 256, 256)
TAPS = (1, 4, 7, 9, 11)  # the ReLUs after conv1..conv5 in torchvision's alexnet.features
SHIFT = (-0.030, -0.088, -0.188)
SCALE = (0.458, 0.448, 0.450)


def alexnet_features() -> nn.Sequential:
    """torchvision's alexnet().features up to conv5's ReLU, with the same module indices (state-dict keys)."""
    return nn.Sequential(
        nn.Conv2d(3, 64, 11, stride=4, padding=2), nn.ReLU(), nn.MaxPool2d(3, 2),
        nn.Conv2d(64, 192, 5, padding=2), nn.ReLU(), nn.MaxPool2d(3, 2),
        nn.Conv2d(192, 384, 3, padding=1), nn.ReLU(),
        nn.Conv2d(384, 256, 3, padding=1), nn.ReLU(),
        nn.Conv2d(256, 256, 3, padding=1), nn.ReLU())


def find_backbone(path: str = "") -> Path:
    return find_weights(path, "LPIPS_BACKBONE", BACKBONE_FILE, "LPIPS backbone")


def find_heads(path: str = "") -> Path:
    if path:
        if not Path(path).is_file():
            raise InputError(f"LPIPS heads {path} not found: pass lpips' weights/v0.1/alex.pth")
        return Path(path)
    spec = importlib.util.find_spec("lpips")
    if spec is None or not spec.submodule_search_locations:
        raise InputError("LPIPS heads not found: pip install lpips (its weights/v0.1/alex.pth) or pass the file")
    return Path(next(iter(spec.submodule_search_locations))) / "weights" / "v0.1" / "alex.pth"


class LayerDistance(nn.Module):
    """The LPIPS recipe over any feature network: its tapped outputs unit-normalised over channels, squared
    differences weighted by a 1x1 convolution per tap, averaged over space (or upsampled, for the map) and
    summed. Images (N, 3, H, W) in [0, 1]; LPIPS and ST-LPIPS differ only in the network and its weights."""

    def __init__(self, features: nn.Sequential, taps: tuple[int, ...], channels: tuple[int, ...]) -> None:
        super().__init__()
        self.features, self.taps = features, taps
        self.lins = nn.ModuleList(nn.Conv2d(c, 1, 1, bias=False) for c in channels)
        self.register_buffer("shift", torch.tensor(SHIFT).view(1, 3, 1, 1))
        self.register_buffer("scale", torch.tensor(SCALE).view(1, 3, 1, 1))

    def _layers(self, a: torch.Tensor, b: torch.Tensor) -> list[torch.Tensor]:
        x = torch.cat([a, b]) * 2 - 1
        x = (x - self.shift) / self.scale
        out = []
        for index, module in enumerate(self.features):
            x = module(x)
            if index in self.taps:
                fa, fb = x.chunk(2)
                fa = fa / (fa.pow(2).sum(1, keepdim=True).sqrt() + 1e-10)
                fb = fb / (fb.pow(2).sum(1, keepdim=True).sqrt() + 1e-10)
                out.append(self.lins[len(out)]((fa - fb) ** 2))
        return out

    def distance(self, a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
        """The distance with gradients (the finetuning loss); the network's own weights stay fixed."""
        return sum(layer.mean(dim=(2, 3)) for layer in self._layers(a, b))[:, 0]

    @torch.no_grad()
    def forward(self, a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
        return self.distance(a, b)

    @torch.no_grad()
    def map(self, a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
        size = a.shape[-2:]
        return sum(F.interpolate(layer, size=size, mode="bilinear", align_corners=False)
                   for layer in self._layers(a, b))[:, 0]


class Lpips(LayerDistance):
    """LPIPS distance between images (N, 3, H, W) in [0, 1]; `map` gives it per pixel (N, H, W)."""

    def __init__(self, backbone: str = "", heads: str = "") -> None:
        super().__init__(alexnet_features(), TAPS, CHANNELS)
        self._load(find_backbone(backbone), find_heads(heads))
        self.eval().requires_grad_(False)

    def _load(self, backbone: Path, heads: Path) -> None:
        state = _read(backbone)
        try:
            self.features.load_state_dict({k[len("features."):]: v for k, v in state.items()
                                           if k.startswith("features.")})
            lins = _read(heads)
            for k, lin in enumerate(self.lins):
                lin.weight.data.copy_(lins[f"lin{k}.model.1.weight"])
        except (RuntimeError, KeyError) as exc:
            raise InputError(f"{backbone} / {heads} do not hold AlexNet LPIPS weights ({str(exc).splitlines()[0]})"
                             ) from exc


def _read(path: Path) -> dict:
    try:
        return torch.load(path, map_location="cpu", weights_only=True)
    except Exception as exc:  # torch raises several types for unreadable files
        raise InputError(f"{path} is not a readable torch weights file ({str(exc).splitlines()[0]})") from exc
