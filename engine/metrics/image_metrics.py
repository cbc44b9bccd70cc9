"""Image metrics shared by training and evaluation: PSNR, SSIM (also the training loss), identity mIoU.

Images are float tensors in [0, 1], shape (H, W, C). SSIM uses the usual 11x11 Gaussian window
(sigma 1.5) with constants (0.01, 0.03) and 'same' zero padding, as the 3DGS reference code does.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import torch
import torch.nn.functional as F


def mean_and_worst(values: list[float]) -> dict:
    """A score over views as its mean, its worst (lowest) view and the number of views: a mean alone hides the one
    view where a stage failed."""
    return {"mean": float(sum(values) / len(values)) if values else None,
            "worst": float(min(values)) if values else None, "views": len(values)}


def psnr_from_mse(mse: float) -> float:
    """PSNR in dB of images in [0, 1] with mean squared error `mse`."""
    return float("inf") if mse == 0 else 10 * math.log10(1.0 / mse)


def psnr(a: torch.Tensor, b: torch.Tensor) -> float:
    return psnr_from_mse(torch.mean((a.float() - b.float()) ** 2).item())


def masked_psnr(image: np.ndarray, truth: np.ndarray, where: np.ndarray) -> float:
    """PSNR of two 8-bit (H, W, 3) images over the pixels `where` (H, W) holds."""
    return psnr(torch.from_numpy(image[where]) / 255.0, torch.from_numpy(truth[where]) / 255.0)


@functools.cache
def _window(size: int, sigma: float, device: torch.device, dtype: torch.dtype) -> torch.Tensor:
    """The normalised 1-D Gaussian window, built once per device (a training step blurs twice)."""
    x = torch.arange(size, device=device, dtype=dtype) - size // 2
    g = torch.exp(-(x**2) / (2 * sigma**2))
    return g / g.sum()


def blur(t: torch.Tensor, size: int = 11, sigma: float = 1.5) -> torch.Tensor:
    """SSIM's Gaussian window over each channel of (B, C, H, W), 'same' zero padding, as two 1-D passes.
    The window is symmetric and zero-padded, so this operator is its own adjoint (the training loss's
    backward, engine.train.photometric_loss, blurs its gradients with it)."""
    g, channels = _window(size, sigma, t.device, t.dtype), t.shape[1]
    t = F.conv2d(t, g.view(1, 1, 1, size).expand(channels, 1, 1, size), padding=(0, size // 2), groups=channels)
    return F.conv2d(t, g.view(1, 1, size, 1).expand(channels, 1, size, 1), padding=(size // 2, 0), groups=channels)


@dataclass
class SsimParts:
    """SSIM's local statistics of x against y, each (B, C, H, W): value = a1 a2 / (b1 b2)."""

    mu_x: torch.Tensor
    mu_y: torch.Tensor
    a1: torch.Tensor  # 2 mu_x mu_y + c1
    a2: torch.Tensor  # 2 cov_xy + c2
    b1: torch.Tensor  # mu_x^2 + mu_y^2 + c1
    b2: torch.Tensor  # var_x + var_y + c2
    value: torch.Tensor


def ssim_parts(x: torch.Tensor, y: torch.Tensor) -> SsimParts:
    """SSIM's terms for images (B, C, H, W); all five local means come from one blur."""
    channels = x.shape[1]
    mu_x, mu_y, xx, yy, xy = blur(torch.cat([x, y, x * x, y * y, x * y], dim=1)).split(channels, dim=1)
    c1, c2 = 0.01**2, 0.03**2
    mu_xy = mu_x * mu_y
    a1, a2 = 2 * mu_xy + c1, 2 * (xy - mu_xy) + c2
    b1, b2 = mu_x**2 + mu_y**2 + c1, (xx - mu_x**2) + (yy - mu_y**2) + c2
    return SsimParts(mu_x, mu_y, a1, a2, b1, b2, (a1 * a2) / (b1 * b2))


def ssim_map(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """Per-pixel SSIM (H, W), averaged over channels, for images (H, W, C)."""
    return ssim_parts(a.permute(2, 0, 1)[None], b.permute(2, 0, 1)[None]).value[0].mean(dim=0)


def ssim(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """Mean SSIM of images (H, W, C); differentiable (the training loss uses it)."""
    return ssim_map(a, b).mean()


class IoUCounter:
    """Accumulates per-class intersections and unions over views; mIoU over classes in the ground truth."""

    def __init__(self, num_classes: int) -> None:
        self.inter = torch.zeros(num_classes, dtype=torch.float64)
        self.union = torch.zeros(num_classes, dtype=torch.float64)
        self.present = torch.zeros(num_classes, dtype=torch.bool)

    def add(self, pred: torch.Tensor, truth: torch.Tensor) -> None:
        n = len(self.inter)
        pred, truth = pred.flatten().long().cpu(), truth.flatten().long().cpu()
        hist = torch.bincount(truth * n + pred, minlength=n * n).reshape(n, n).double()
        inter = hist.diag()
        self.inter += inter
        self.union += hist.sum(0) + hist.sum(1) - inter
        self.present |= hist.sum(1) > 0

    def iou(self) -> dict[int, float]:
        """IoU of each class present in the ground truth."""
        present = torch.nonzero(self.present).flatten()
        return {int(c): float(self.inter[c] / self.union[c].clamp_min(1)) for c in present}

    def miou(self) -> float:
        iou = self.inter[self.present] / self.union[self.present].clamp_min(1)
        return float(iou.mean()) if len(iou) else float("nan")
