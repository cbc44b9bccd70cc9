"""Distances between two sets of image features: FID's Frechet distance and KID.

FID (Heusel et al.): ||mu_a - mu_b||^2 + Tr(S_a + S_b - 2 (S_a S_b)^(1/2)), covariances with N - 1 as
numpy's np.cov. The trace of the matrix square root is the sum of square roots of the eigenvalues of
S_a^(1/2) S_b S_a^(1/2), a symmetric PSD matrix: an eigendecomposition in float64 instead of scipy's
sqrtm, which returns complex noise when a covariance is singular, as it always is with fewer images than
2048 features (our test sets have 10 to 20 views).

KID (Binkowski et al.): the unbiased MMD^2 with the cubic polynomial kernel k(x, y) = (x.y / d + 1)^3,
over the whole sets (torch-fidelity averages it over random subsets of 1000, more images than we have).
Unlike FID it is unbiased with few images, which is why it stands beside FID in our tables.
"""

from __future__ import annotations

import numpy as np


def _sqrt_psd(matrix: np.ndarray) -> np.ndarray:
    values, vectors = np.linalg.eigh(matrix)
    return (vectors * np.sqrt(np.clip(values, 0, None))) @ vectors.T


def frechet_distance(a: np.ndarray, b: np.ndarray) -> float:
    """FID between feature sets a (N, D) and b (M, D), N, M >= 2."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    mu_a, mu_b = a.mean(0), b.mean(0)
    cov_a, cov_b = np.atleast_2d(np.cov(a, rowvar=False)), np.atleast_2d(np.cov(b, rowvar=False))
    root_a = _sqrt_psd(cov_a)
    cross = np.sqrt(np.clip(np.linalg.eigvalsh(root_a @ cov_b @ root_a), 0, None)).sum()
    return float(((mu_a - mu_b) ** 2).sum() + np.trace(cov_a) + np.trace(cov_b) - 2 * cross)


def kernel_inception_distance(a: np.ndarray, b: np.ndarray) -> float:
    """KID between feature sets a (N, D) and b (M, D): unbiased MMD^2, cubic polynomial kernel."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    d = a.shape[1]
    k_aa, k_bb, k_ab = ((a @ a.T / d + 1) ** 3, (b @ b.T / d + 1) ** 3, (a @ b.T / d + 1) ** 3)
    n, m = len(a), len(b)
    return float((k_aa.sum() - np.trace(k_aa)) / (n * (n - 1)) + (k_bb.sum() - np.trace(k_bb)) / (m * (m - 1))
                 - 2 * k_ab.mean())
