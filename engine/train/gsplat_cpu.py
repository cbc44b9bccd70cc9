"""Torch versions of the two CUDA-only ops gsplat's MCMCStrategy calls, so budgeted runs work on the CPU.

gsplat 1.5.3's strategy code is pure torch except `compute_relocation` (the MCMC paper's Eq. 9) and
`quat_scale_to_covar_preci` (used for noise injection). On CUDA nothing is replaced; on the CPU these two
names inside gsplat.strategy.ops are pointed at the functions below. benchmarks/rasterizer_agreement.py compares
them with the CUDA kernels on the GPU.
"""

from __future__ import annotations

import torch

from engine.render.rasterize_reference import quat_scale_to_covar


def compute_relocation(opacities: torch.Tensor, scales: torch.Tensor, ratios: torch.Tensor,
                       binoms: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """New opacities (N,) and scales (N, 3) when a Gaussian is split into `ratios` copies."""
    n_max = binoms.shape[0]
    ratios = ratios.clamp(1, n_max).int()
    new_opacities = 1.0 - torch.pow(1.0 - opacities, 1.0 / ratios)
    i = torch.arange(1, n_max + 1, device=opacities.device)[:, None]  # (n_max, 1)
    k = torch.arange(n_max, device=opacities.device)[None, :]  # (1, n_max)
    signs = torch.where(k % 2 == 0, 1.0, -1.0)
    terms = binoms[i - 1, k] * signs / torch.sqrt(k + 1.0)  # (n_max, n_max), binoms zero where k > i-1
    terms = terms * (k <= i - 1)
    powers = new_opacities[:, None] ** (k + 1)  # (N, n_max)
    per_i = powers @ terms.T  # (N, n_max): inner sum for each i
    use = (i.T <= ratios[:, None])  # (N, n_max)
    denom = (per_i * use).sum(-1)
    return new_opacities, scales * (opacities / denom)[:, None]


def quat_scale_to_covar_preci(quats, scales, compute_covar=True, compute_preci=True, triu=False):
    covar = quat_scale_to_covar(quats, scales)
    preci = torch.linalg.inv(covar) if compute_preci else None
    return (covar if compute_covar else None), preci


def enable_cpu_mcmc() -> None:
    """Point gsplat's MCMC helpers at the torch versions (CPU only)."""
    import gsplat.strategy.ops as ops

    ops.compute_relocation = compute_relocation
    ops.quat_scale_to_covar_preci = quat_scale_to_covar_preci
