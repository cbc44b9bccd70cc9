"""Image metrics shared by training and evaluation: PSNR, SSIM (also the training loss), identity mIoU.

Images are float tensors in [0, 1], shape (H, W, C). SSIM uses the usual 11x11 Gaussian window
(sigma 1.5) with constants (0.01, 0.03) and 'same' zero padding, as the 3DGS reference code does.
"""

from __future__ import annotations

import math

import torch
import torch.nn.functional as F


def psnr_from_mse(mse: float) -> float:
    """PSNR in dB of images in [0, 1] with mean squared error `mse`."""
    return float("inf") if mse == 0 else 10 * math.log10(1.0 / mse)


def psnr(a: torch.Tensor, b: torch.Tensor) -> float:
    return psnr_from_mse(torch.mean((a.float() - b.float()) ** 2).item())


def _gaussian_1d(size: int, sigma: float, device, dtype) -> torch.Tensor:
    x = torch.arange(size, device=device, dtype=dtype) - size // 2
    g = torch.exp(-(x**2) / (2 * sigma**2))
    return g / g.sum()


def ssim_map(a: torch.Tensor, b: torch.Tensor, size: int = 11, sigma: float = 1.5) -> torch.Tensor:
    """Per-pixel SSIM (H, W), averaged over channels, for images (H, W, C)."""
    x, y = a.permute(2, 0, 1)[None], b.permute(2, 0, 1)[None]
    channels = x.shape[1]
    g = _gaussian_1d(size, sigma, x.device, x.dtype)
    rows = g.view(1, 1, 1, size).expand(5 * channels, 1, 1, size)
    cols = g.view(1, 1, size, 1).expand(5 * channels, 1, size, 1)

    def blur(t: torch.Tensor) -> torch.Tensor:  # separable window: two 1-D passes instead of one 11x11
        t = F.conv2d(t, rows, padding=(0, size // 2), groups=t.shape[1])
        return F.conv2d(t, cols, padding=(size // 2, 0), groups=t.shape[1])

    stats = blur(torch.cat([x, y, x * x, y * y, x * y], dim=1))  # all five local means in one call
    mu_x, mu_y, xx, yy, xy = stats.split(channels, dim=1)
    sxx, syy, sxy = xx - mu_x**2, yy - mu_y**2, xy - mu_x * mu_y
    c1, c2 = 0.01**2, 0.03**2
    value = ((2 * mu_x * mu_y + c1) * (2 * sxy + c2)) / ((mu_x**2 + mu_y**2 + c1) * (sxx + syy + c2))
    return value[0].mean(dim=0)


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
