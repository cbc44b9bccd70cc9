"""FID's time on one benchmark cell's feature sets: 10 test views, 2048 Inception features (CPU, one thread).

    OMP_NUM_THREADS=1 PYTHONPATH=. python docs/benchmarks/metrics/fid_speed.py

Times engine.metrics.distribution_metrics.frechet_distance (the singular values of A B') against the two 2048 x 2048
eigendecompositions it replaced (the definition, as tests/test_metrics.py writes it), on the same features.
"""

import time

import numpy as np

from engine.metrics.distribution_metrics import frechet_distance


def by_definition(a: np.ndarray, b: np.ndarray) -> float:
    cov_a, cov_b = np.cov(a, rowvar=False), np.cov(b, rowvar=False)
    values, vectors = np.linalg.eigh(cov_a)
    root_a = (vectors * np.sqrt(np.clip(values, 0, None))) @ vectors.T
    cross = np.sqrt(np.clip(np.linalg.eigvalsh(root_a @ cov_b @ root_a), 0, None)).sum()
    return float(((a.mean(0) - b.mean(0)) ** 2).sum() + np.trace(cov_a) + np.trace(cov_b) - 2 * cross)


rng = np.random.default_rng(0)
a, b = np.abs(rng.normal(0, 1, (10, 2048))), np.abs(rng.normal(0.1, 1, (10, 2048)))
for name, fid in (("eigendecompositions (before)", by_definition), ("singular values of A B' (now)", frechet_distance)):
    start = time.perf_counter()
    value = fid(a, b)
    print(f"{name}: {time.perf_counter() - start:.3f} s, FID {value:.6f}")
