"""3DGS's photometric loss, (1 - w) L1 + w (1 - SSIM), with its gradient written out instead of traced.

Why: autograd records SSIM as about 25 small operations and replays about 40 in the backward pass, every
training step. Their GPU time is small, but the training loop is bound by the host's time to launch
kernels (docs/BENCHMARKS.md, "Training"), so each launch saved is time saved. The forward
pass is engine.metrics.image_metrics.ssim_parts (the metric's own code); the backward pass is the closed form
below, checked against autograd in tests/train/test_training.py.

With S = a1 a2 / (b1 b2) per pixel and channel, the five blurred statistics m_x, m_y, E[x^2], E[y^2],
E[xy] (blur G), and only x (the render) needing a gradient:
  dS/dm_x = 2 (m_y (a2 - a1) - m_x S (b2 - b1)) / (b1 b2),  dS/dE[x^2] = -S / b2,  dS/dE[xy] = 2 a1 / (b1 b2)
  dL/dx = G(u dS/dm_x) + 2 x G(u dS/dE[x^2]) + y G(u dS/dE[xy])   (G is its own adjoint)
where u = -w / (C H W) is the loss's derivative with respect to each S.

`fused`: the SSIM term from the registry package fussim's fused CUDA kernel instead (the same window and
constants), a lead of the training-speed issue measured in docs/BENCHMARKS.md ("Training"); never the default
until it measures faster at equal quality.
"""

from __future__ import annotations

import torch

from engine.base.errors import InputError
from engine.metrics.image_metrics import blur, ssim_parts


class _Photometric(torch.autograd.Function):
    @staticmethod
    def forward(ctx, rgb: torch.Tensor, target: torch.Tensor, ssim_weight: float) -> torch.Tensor:
        x, y = _channels_first(rgb), _channels_first(target)
        parts = ssim_parts(x, y)
        ctx.save_for_backward(x, y, parts.mu_x, parts.mu_y, parts.a1, parts.a2, parts.b1, parts.b2, parts.value)
        ctx.ssim_weight, ctx.single = ssim_weight, rgb.dim() == 3
        l1 = (x - y).abs().mean()
        return (1 - ssim_weight) * l1 + ssim_weight * (1 - parts.value.mean())

    @staticmethod
    def backward(ctx, grad: torch.Tensor):
        x, y, mu_x, mu_y, a1, a2, b1, b2, value = ctx.saved_tensors
        w, count = ctx.ssim_weight, x.numel()
        inv = 1 / (b1 * b2)
        d_mu = 2 * inv * (mu_y * (a2 - a1) - mu_x * value * (b2 - b1))
        d_xx = -value / b2
        d_xy = 2 * a1 * inv
        g_mu, g_xx, g_xy = blur(torch.cat([d_mu, d_xx, d_xy], dim=1)).split(x.shape[1], dim=1)
        d_x = (-w / count) * (g_mu + 2 * x * g_xx + y * g_xy) + ((1 - w) / count) * torch.sign(x - y)
        d_x = (grad * d_x).permute(0, 2, 3, 1)
        return (d_x[0] if ctx.single else d_x), None, None


def photometric_loss(rgb: torch.Tensor, target: torch.Tensor, ssim_weight: float, fused: bool = False
                     ) -> torch.Tensor:
    """(1 - ssim_weight) mean |rgb - target| + ssim_weight (1 - SSIM) for images (H, W, C), or for a batch of
    views of one size (B, H, W, C): then the mean of their losses, in the launches of one; differentiable in
    `rgb` only (the target is data)."""
    if not fused:
        return _Photometric.apply(rgb, target, ssim_weight)
    x, y = _channels_first(rgb), _channels_first(target)
    return (1 - ssim_weight) * (x - y).abs().mean() + ssim_weight * (1 - fused_ssim()(x, y))


def _channels_first(images: torch.Tensor) -> torch.Tensor:
    """(H, W, C) or (B, H, W, C) as (B, C, H, W), on a GPU copied contiguous. Why the copy: a permuted view keeps
    the channels last in memory, and the SSIM blur's grouped convolution then ran a cuDNN NHWC engine: on an H200,
    forward and backward of four 640x480 views took 4.56 ms as a permuted view, 1.71 ms copied. On the CPU the
    view is faster (2 cores, four 160x120 views: 8.6 ms against 11.1; benchmarks/loss_speed.py)."""
    view = images.permute(2, 0, 1)[None] if images.dim() == 3 else images.permute(0, 3, 1, 2)
    return view.contiguous() if view.is_cuda else view


def fused_ssim():
    """fussim's fused_ssim, or one line saying how to get it."""
    try:
        from fussim import fused_ssim as ssim
    except ImportError as error:
        raise InputError(f"--fused-ssim needs the fussim package on a CUDA machine ({error}): "
                         "pip install fussim, or leave --fused-ssim off") from error
    return ssim
