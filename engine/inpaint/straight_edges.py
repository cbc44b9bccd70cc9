"""Straight edges that cross a hole: found on the known ring around it, seen on both sides, and continued through
it as lines, so that a fill from the border keeps each side's colour on its own side.

Why: the commonest edge across a removed object's footprint on a support plane is straight (a shadow's edge from
a trunk, a pole or a roof line; a slab's or a rug's border; a skirting board), and a line on a plane stays a line
in every view. A fill from the border that carries colour along the local edge direction (coherence transport)
loses that direction where the hole is wide: its direction field in the hole is a mean over the whole border,
and the edge comes out wavy, a lit bay cut into the band or a dark blotch past it (held-out statue_s100 at
274f783: the fill below the unfilled hole on 2 of 3 training seeds). A line seen entering and leaving the hole,
with the same two colours on its two sides at both ends, is drawn straight through; the fill then reads each
hole pixel's colour only from known pixels on the same sides of every such line.

A candidate is a Hough line through the ring's edge pixels (Canny on the smoothed luminance, the hole's own
outline left out); it is kept where it crosses the hole and, at its entry and its exit, the ring shows the two
sides differing by at least MIN_CONTRAST in luminance at each of OFFSETS px from it, the same way round, and
each side's colour at one end within SIDE_MATCH of the contrast of the same side's at the other. At most MAX_LINES
lines, the highest contrast first (a grain's many weak edges outvote a shadow's one in the Hough count), none
within DUPLICATE_RHO px and DUPLICATE_THETA of one kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

RING = 12  # px of known image around the hole that lines are read from
OUTLINE = 2  # px next to the hole left out of the edge map (the hole's placeholder makes an edge there)
SMOOTH = 1.5  # px: luminance smoothing before the edges (a texture's grain is not an edge)
MIN_VOTES = 10  # edge pixels on the ring a candidate line must pass through
CANDIDATES = 64  # Hough lines tried (those with most votes); the highest contrast kept first
OFFSETS = (3.0, 6.0, 9.0)  # px either side of a line that its two sides' colours are read at: a step, not a vein
MIN_CONTRAST = 0.08  # luminance (0-1) between a line's two sides at both of its ends
SIDE_MATCH = 0.5  # each side's luminance at the two ends within this share of the contrast
MAX_LINES = 3
DUPLICATE_RHO = 2 * OFFSETS[0] + 1  # px: a line this near a stronger parallel one reads the same edge
DUPLICATE_THETA = np.radians(6.0)


@dataclass(frozen=True)
class Line:
    """The points x cos(theta) + y sin(theta) = rho (pixel centres, x along columns)."""

    rho: float
    theta: float

    def signed(self, ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
        """Signed distance of pixels from the line, px."""
        return xs * np.cos(self.theta) + ys * np.sin(self.theta) - self.rho


def normalised_blur(values: np.ndarray, weight: np.ndarray, sigma: float) -> np.ndarray:
    """Gaussian mean of `values` (H, W[, C]) over the pixels `weight` (H, W) marks (0 where none is near): a
    blur that reads nothing from the hole's placeholder."""
    blur = lambda a: cv2.GaussianBlur(a, (0, 0), sigma, borderType=cv2.BORDER_REPLICATE)  # noqa: E731
    w = blur(weight)
    v = blur(values * (weight[..., None] if values.ndim == 3 else weight))
    return v / np.maximum(w if values.ndim == 2 else w[..., None], 1e-6)


def _grown(mask: np.ndarray, pixels: int) -> np.ndarray:
    """`mask` grown by a square of `pixels` each way: the ring reaches the hole's corners as far as its sides
    (engine.io.masks.dilate's disc reads less there: it lost the veined test's edge on one noise seed)."""
    return cv2.dilate(mask.astype(np.uint8), np.ones((2 * pixels + 1,) * 2, np.uint8)).astype(bool)


def _edges(grey: np.ndarray, mask: np.ndarray, known: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ring's edge pixels (uint8 0/255) and the ring itself (`known`: the pixels outside the hole)."""
    ring = _grown(mask, RING) & known
    away = ~_grown(mask, OUTLINE)
    smooth = normalised_blur(grey.astype(np.float32), known.astype(np.float32), SMOOTH)
    grey8 = np.clip(smooth * 255.0, 0, 255).astype(np.uint8)
    step = 8.0 * 255 * MIN_CONTRAST / (SMOOTH * np.sqrt(2 * np.pi))  # Sobel's peak across a smoothed step
    edges = cv2.Canny(grey8, step / 2, step)
    return np.where(ring & away, edges, 0).astype(np.uint8), ring


def _ends(line: Line, mask: np.ndarray, ring: np.ndarray) -> list[np.ndarray] | None:
    """The ring's points along the line just outside the hole where it enters and where it leaves, as two
    (N, 2) arrays of (y, x); None where the line misses the hole or an end has no ring to read."""
    h, w = mask.shape
    direction = np.array([-np.sin(line.theta), np.cos(line.theta)])  # (dx, dy) along the line
    foot = line.rho * np.array([np.cos(line.theta), np.sin(line.theta)])
    t = np.arange(-(h + w), h + w, 0.5)
    xs, ys = foot[0] + t * direction[0], foot[1] + t * direction[1]
    inside = (xs >= 0) & (xs <= w - 1) & (ys >= 0) & (ys <= h - 1)
    xs, ys, t = xs[inside], ys[inside], t[inside]
    yi, xi = np.rint(ys).astype(int), np.rint(xs).astype(int)
    in_hole = mask[yi, xi]
    if in_hole.sum() < 6:
        return None
    first, last = t[in_hole].min(), t[in_hole].max()
    before = ring[yi, xi] & (t < first) & (t >= first - RING)
    after = ring[yi, xi] & (t > last) & (t <= last + RING)
    if before.sum() < 4 or after.sum() < 4:
        return None
    return [np.stack([ys[before], xs[before]], 1), np.stack([ys[after], xs[after]], 1)]


def _sides(line: Line, points: np.ndarray, grey: np.ndarray, known: np.ndarray) -> np.ndarray | None:
    """(len(OFFSETS), 2): median luminance at each offset on the line's positive and negative sides of
    `points`, known pixels only; None where an offset has too few."""
    normal = np.array([np.sin(line.theta), np.cos(line.theta)])  # (dy, dx)
    medians = np.zeros((len(OFFSETS), 2))
    for row, offset in enumerate(OFFSETS):
        for column, sign in enumerate((1.0, -1.0)):
            at = np.rint(points + sign * offset * normal).astype(int)
            at = at[(at[:, 0] >= 0) & (at[:, 0] < grey.shape[0]) & (at[:, 1] >= 0) & (at[:, 1] < grey.shape[1])]
            at = at[known[at[:, 0], at[:, 1]]]
            if len(at) < 3:
                return None
            medians[row, column] = np.median(grey[at[:, 0], at[:, 1]])
    return medians


def _contrast_on_both_sides(line: Line, grey: np.ndarray, mask: np.ndarray, known: np.ndarray,
                            ring: np.ndarray) -> float:
    """The least luminance contrast between the line's two sides, at every offset, where it enters the hole and
    where it leaves; 0 where it misses the hole, where one of them differs the other way round, or where the
    two ends' sides have other colours. A step (a shadow's edge, a border) passes at every offset; a vein in a
    grain that happens to run straight for a while differs at one offset and not the next."""
    ends = _ends(line, mask, ring)
    if ends is None:
        return 0.0
    sides = [_sides(line, points, grey, known) for points in ends]
    if sides[0] is None or sides[1] is None:
        return 0.0
    differences = np.concatenate([sides[0][:, 0] - sides[0][:, 1], sides[1][:, 0] - sides[1][:, 1]])
    contrast = float(np.abs(differences).min())
    if contrast < MIN_CONTRAST or len(set(np.sign(differences))) > 1:
        return 0.0
    (a0, b0), (a1, b1) = sides[0].mean(0), sides[1].mean(0)
    same = abs(a0 - a1) <= SIDE_MATCH * contrast and abs(b0 - b1) <= SIDE_MATCH * contrast
    return contrast if same else 0.0


def _duplicate(line: Line, kept: list[Line]) -> bool:
    """Whether a kept line is nearly the same line (Hough's (rho, theta) and (-rho, theta - pi) are one line)."""
    for other in kept:
        dtheta = abs(line.theta - other.theta)
        if dtheta < DUPLICATE_THETA and abs(line.rho - other.rho) < DUPLICATE_RHO:
            return True
        if abs(dtheta - np.pi) < DUPLICATE_THETA and abs(line.rho + other.rho) < DUPLICATE_RHO:
            return True
    return False


def crossing_lines(grey: np.ndarray, mask: np.ndarray) -> list[Line]:
    """The straight edges (module docstring) that cross the hole `mask` in `grey` (H, W) luminance in 0-1."""
    if not mask.any() or mask.all():
        return []
    known = ~mask  # once, for every candidate's sides
    edges, ring = _edges(grey, mask, known)
    found = cv2.HoughLines(edges, 1, np.pi / 180, MIN_VOTES)
    lines = [Line(float(rho), float(theta)) for rho, theta in ([] if found is None else found[:CANDIDATES, 0])]
    contrast = [_contrast_on_both_sides(line, grey, mask, known, ring) for line in lines]
    kept: list[Line] = []
    for index in np.argsort(contrast)[::-1]:
        if contrast[index] > 0 and not _duplicate(lines[index], kept):
            kept.append(lines[index])
            if len(kept) == MAX_LINES:
                break
    return kept


def side_labels(lines: list[Line], shape: tuple[int, int]) -> np.ndarray:
    """(H, W) int: which side of each line every pixel lies on, one bit a line (0 everywhere without lines)."""
    ys, xs = np.mgrid[:shape[0], :shape[1]].astype(np.float32)
    labels = np.zeros(shape, np.int64)
    for bit, line in enumerate(lines):
        labels |= (line.signed(ys, xs) > 0).astype(np.int64) << bit
    return labels
