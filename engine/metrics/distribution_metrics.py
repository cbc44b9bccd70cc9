"""Distances between two sets of image features: FID's Frechet distance and KID.

FID (Heusel et al.): ||mu_a - mu_b||^2 + Tr(S_a + S_b - 2 (S_a S_b)^(1/2)), covariances with N - 1 as
numpy's np.cov. The trace of the matrix square root is the sum of square roots of the eigenvalues of S_a S_b.
With A and B the centred features (N x D, M x D), S_a = A'A / (N - 1) and S_b = B'B / (M - 1), and S_a S_b has
the nonzero eigenvalues of (A B')(A B')' / ((N - 1)(M - 1)): the trace is the sum of the singular values of the
N x M matrix A B', over sqrt((N - 1)(M - 1)) (with more images than features, of R_a R_b' from A = Q_a R_a).
Exact, in float64, and no D x D matrix is decomposed. Why: our test sets have 10 to 20 views against 2048
features, and the two 2048 x 2048 eigendecompositions this replaced took 5.1 s a FID on one CPU thread (0.001 s
now), with four FIDs in every benchmark cell (docs/BENCHMARKS.md). Like them, and unlike scipy's sqrtm
(complex noise when a covariance is singular, as it always is with fewer images than features), it stays real.

KID (Binkowski et al.): the unbiased MMD^2 with the cubic polynomial kernel k(x, y) = (x.y / d + 1)^3,
over the whole sets (torch-fidelity averages it over random subsets of 1000, more images than we have).
Unlike FID it is unbiased with few images, which is why it stands beside FID in our tables.
"""

from __future__ import annotations

import numpy as np


def _rows(centred: np.ndarray) -> np.ndarray:
    """At most D rows with the same Gram matrix X'X: R of X = QR when there are more samples than features (A B'
    and R_a R_b' have the same singular values), else X itself."""
    return np.linalg.qr(centred, mode="r") if len(centred) > centred.shape[1] else centred


def frechet_distance(a: np.ndarray, b: np.ndarray) -> float:
    """FID between feature sets a (N, D) and b (M, D), N, M >= 2 (see the module docstring)."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    centred_a, centred_b = a - a.mean(0), b - b.mean(0)
    scale_a, scale_b = len(a) - 1, len(b) - 1
    factor_a, factor_b = _rows(centred_a), _rows(centred_b)
    cross = np.linalg.svd(factor_a @ factor_b.T, compute_uv=False).sum() / np.sqrt(scale_a * scale_b)
    traces = (centred_a**2).sum() / scale_a + (centred_b**2).sum() / scale_b
    return float(((a.mean(0) - b.mean(0)) ** 2).sum() + traces - 2 * cross)


def kernel_inception_distance(a: np.ndarray, b: np.ndarray) -> float:
    """KID between feature sets a (N, D) and b (M, D): unbiased MMD^2, cubic polynomial kernel."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    d = a.shape[1]
    k_aa, k_bb, k_ab = ((a @ a.T / d + 1) ** 3, (b @ b.T / d + 1) ** 3, (a @ b.T / d + 1) ** 3)
    n, m = len(a), len(b)
    return float((k_aa.sum() - np.trace(k_aa)) / (n * (n - 1)) + (k_bb.sum() - np.trace(k_bb)) / (m * (m - 1))
                 - 2 * k_ab.mean())
