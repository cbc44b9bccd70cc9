"""The cast shadow's gain on test_effects' checker floor (its shadow darkens the light to 0.2, so the true gain is
5 in every channel) at three light azimuths: what find_shadow returns, and the lit edge's and the dark samples'
per-channel medians, means and 10% trimmed means against each other. Run from the repository root:

    PYTHONPATH=. python docs/benchmarks/effects/session25/gain_probe.py
"""

import math
import sys

import numpy as np

sys.path.insert(0, "tests")
from test_effects import gaussians, shadow_of, shadow_scene, view_samples  # noqa: E402

from engine.io.image_io import srgb_to_linear  # noqa: E402


def trimmed(x: np.ndarray, cut: float = 10.0) -> np.ndarray:
    lo, hi = np.percentile(x, [cut, 100 - cut], axis=0)
    inside = (x >= lo) & (x <= hi)
    return (x * inside).sum(0) / inside.sum(0)


for azimuth in (30, 75, 120):
    el, az = math.radians(40), math.radians(azimuth)
    light = np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    floor, lit, seen, truth, box = shadow_scene(light)
    samples = view_samples(floor, seen)
    shadow = shadow_of(gaussians(floor, seen), gaussians(box, np.full((len(box), 3), 0.9)), samples)
    c = srgb_to_linear(samples.colors[shadow.pick])
    lit_c, dark_c = c[shadow.lit], c[shadow.dark]
    medians = np.median(lit_c, 0) / np.median(dark_c, 0)
    print(f"azimuth {azimuth}: find_shadow {np.round(shadow.gain, 2)}; medians {np.round(medians, 2)}, "
          f"means {np.round(lit_c.mean(0) / dark_c.mean(0), 2)}, "
          f"10% trimmed means {np.round(trimmed(lit_c) / trimmed(dark_c), 2)} (truth 5)")
