"""Real spherical harmonics up to degree 3, with the constants of the reference 3DGS code and gsplat.

Colour = basis(direction) . coefficients as one broadcast product and sum: indexing the coefficients one
band at a time made autograd materialise a full-size gradient per coefficient (1.1 ms a step at 286k
Gaussians), and `einsum` turned the product into 286k tiny batched matrix products (1 ms a step, forward
and backward, on the H200).
The CPU reference rasterizer's colours; on CUDA gsplat's one-kernel evaluation of the same constants is used
(engine.render.rasterize.sh_colors), and benchmarks/rasterizer_agreement.py compares the two, colours and gradients.
"""

from __future__ import annotations

import torch

from engine.formats.splat_ply import SH_C0 as C0
from engine.formats.splat_ply import SH_C1 as C1
from engine.formats.splat_ply import SH_C2 as C2
from engine.formats.splat_ply import SH_C3 as C3


def sh_basis(degree: int, dirs: torch.Tensor) -> torch.Tensor:
    """(N, (degree + 1)^2) SH basis values for unit directions `dirs` (N, 3)."""
    x, y, z = dirs.unbind(-1)
    bands = [torch.full_like(x, C0)]
    if degree >= 1:
        bands += [-C1 * y, C1 * z, -C1 * x]
    if degree >= 2:
        xx, yy, zz = x * x, y * y, z * z
        bands += [C2[0] * x * y, C2[1] * y * z, C2[2] * (2 * zz - xx - yy), C2[3] * x * z, C2[4] * (xx - yy)]
    if degree >= 3:
        bands += [C3[0] * y * (3 * xx - yy), C3[1] * x * y * z, C3[2] * y * (4 * zz - xx - yy),
                  C3[3] * z * (2 * zz - 3 * xx - 3 * yy), C3[4] * x * (4 * zz - xx - yy), C3[5] * z * (xx - yy),
                  C3[6] * x * (xx - 3 * yy)]
    return torch.stack(bands, dim=-1)


def eval_sh(degree: int, sh0: torch.Tensor, sh_rest: torch.Tensor, dirs: torch.Tensor) -> torch.Tensor:
    """Colour (N, 3) towards unit-normalised `dirs` (N, 3) from the DC term `sh0` (N, 1, 3) and the
    higher bands `sh_rest` (N, >= (degree+1)^2 - 1, 3), read in place (no concatenated copy per step)."""
    basis = sh_basis(degree, dirs)
    rgb = C0 * sh0[:, 0]
    if degree > 0:
        rgb = rgb + (basis[:, 1:, None] * sh_rest[:, : basis.shape[1] - 1]).sum(1)
    return rgb
