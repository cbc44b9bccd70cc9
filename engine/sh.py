"""Real spherical harmonics up to degree 3, with the constants of the reference 3DGS code and gsplat.

Used by both rasterizer back ends, so colours agree exactly between them.
"""

from __future__ import annotations

import torch

C0 = 0.28209479177387814
C1 = 0.4886025119029199
C2 = (1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396)
C3 = (-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154, -0.4570457994644658,
      1.445305721320277, -0.5900435899266435)


def eval_sh(degree: int, coeffs: torch.Tensor, dirs: torch.Tensor) -> torch.Tensor:
    """Colour (N, 3) from SH `coeffs` (N, >= (degree+1)^2, 3) towards unit-normalised `dirs` (N, 3)."""
    result = C0 * coeffs[:, 0]
    if degree < 1:
        return result
    x, y, z = dirs.unbind(-1)
    x, y, z = x[:, None], y[:, None], z[:, None]
    result = result - C1 * y * coeffs[:, 1] + C1 * z * coeffs[:, 2] - C1 * x * coeffs[:, 3]
    if degree < 2:
        return result
    xx, yy, zz, xy, yz, xz = x * x, y * y, z * z, x * y, y * z, x * z
    result = (result + C2[0] * xy * coeffs[:, 4] + C2[1] * yz * coeffs[:, 5]
              + C2[2] * (2.0 * zz - xx - yy) * coeffs[:, 6] + C2[3] * xz * coeffs[:, 7]
              + C2[4] * (xx - yy) * coeffs[:, 8])
    if degree < 3:
        return result
    return (result + C3[0] * y * (3 * xx - yy) * coeffs[:, 9] + C3[1] * xy * z * coeffs[:, 10]
            + C3[2] * y * (4 * zz - xx - yy) * coeffs[:, 11]
            + C3[3] * z * (2 * zz - 3 * xx - 3 * yy) * coeffs[:, 12]
            + C3[4] * x * (4 * zz - xx - yy) * coeffs[:, 13] + C3[5] * z * (xx - yy) * coeffs[:, 14]
            + C3[6] * x * (xx - 3 * yy) * coeffs[:, 15])
