"""FID's time on one benchmark cell's feature sets: 10 test views, 2048 Inception features (CPU, one thread).

    OMP_NUM_THREADS=1 PYTHONPATH=. python docs/benchmarks/metrics/fid_speed.py

Times engine.metrics.distribution_metrics.frechet_distance (the singular values of A B') against the two 2048 x 2048
eigendecompositions it replaced (tests/test_metrics.py's frechet_by_definition), on the same features.
"""

import sys
import time
from pathlib import Path

import numpy as np

from engine.metrics.distribution_metrics import frechet_distance

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "tests"))
from test_metrics import frechet_by_definition  # noqa: E402

rng = np.random.default_rng(0)
a, b = np.abs(rng.normal(0, 1, (10, 2048))), np.abs(rng.normal(0.1, 1, (10, 2048)))
for name, fid in (("eigendecompositions (before)", frechet_by_definition),
                  ("singular values of A B' (now)", frechet_distance)):
    start = time.perf_counter()
    value = fid(a, b)
    print(f"{name}: {time.perf_counter() - start:.3f} s, FID {value:.6f}")
