"""Where a scene's points or Gaussians lie, in its own frame: what a user needs to select by a 3D box in a
capture whose scale and axes SfM chose."""

from __future__ import annotations

import numpy as np

from engine.base.errors import InputError


def describe_extent(points: np.ndarray) -> str:
    """Where most of `points` (N, 3) lie, per axis from the 1st to the 99th percentile, in the scene's own
    frame: what a user needs to give a --box in a capture whose scale and axes SfM chose."""
    if len(points) == 0:
        return "no points"
    lo, hi = np.percentile(points, 1, axis=0), np.percentile(points, 99, axis=0)
    return ", ".join(f"{axis} [{a:.3g}, {b:.3g}]" for axis, a, b in zip("xyz", lo, hi, strict=True))


def bounding_box(points: np.ndarray) -> list[float]:
    """x0 y0 z0 x1 y1 z1 around most of `points` (1st to 99th percentile), as --box takes it; [] if none."""
    if len(points) == 0:
        return []
    return [round(float(v), 6) for v in (*np.percentile(points, 1, axis=0), *np.percentile(points, 99, axis=0))]


def inside_box(means: np.ndarray, box: list[float]) -> np.ndarray:
    """(N,) bool: the Gaussians whose centres lie in the box; a box that holds none is an error that says
    where the Gaussians are (a box given in another frame than the scene's would otherwise remove nothing)."""
    if len(box) != 6:
        raise InputError(f"--box needs 6 numbers x0 y0 z0 x1 y1 z1, got {len(box)}")
    lo, hi = np.minimum(box[:3], box[3:]), np.maximum(box[:3], box[3:])
    chosen = np.all((means >= lo) & (means <= hi), axis=1)
    if not chosen.any():
        raise InputError(f"the box {' '.join(f'{v:g}' for v in box)} holds none of the {len(means)} Gaussians; "
                         f"they lie in {describe_extent(means)} (1st to 99th percentile): give a box in that frame")
    return chosen
