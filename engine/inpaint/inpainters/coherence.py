"""Coherence transport (Bornemann and März 2007, "Fast image inpainting based on coherence transport"): a fill
from the hole's border, like Telea's, that carries each colour along the image's own edges instead of the
hole's outline.

Why: Telea's fill weights the border by the hole's shape, so a straight dark band that crosses the hole (a tree's
shadow across a slab, a skirting board, a rug's stripe) enters from both sides and meets lit border in the
middle: the band comes out broken by a pale patch (held-out statue_s100, docs/results/heldout/
`views_e541ab4_statue_s100.jpg`).
Here each hole pixel, taken in order of its distance to the known pixels (one layer of the distance map at a
time, the layer at once), is the weighted mean of the known or already filled pixels within `EPS` px:

    w(x, y) = 1 / |y - x| * exp(-(mu / EPS)^2 / 2 * (c_perp . (y - x))^2)

where c is the direction along the edges at x, the structure tensor's minor eigenvector (gradients at scale
`SIGMA`, averaged over `RHO`, over the known pixels; in the hole, their tensors' mean over the hole's depth, fixed
before the fill: `_across_edges` says why the paper's tensor of the growing fill is not used), and mu = `KAPPA` x
its coherence (0 where the neighbourhood has no one direction: there the weights are Telea-like 1/r and the fill is
smooth). The published parameters (eps 5, kappa 25, sigma 1.4, rho 4). Where it loses: on a wall's fine vertical
grain it carried a dark rim at the hole's border down the wall (Ref -1.64 dB against Telea on wallmount_s8, e541ab4).

Where the hole is wide, the direction in it is a mean over the whole border, and a straight edge across it (a
shadow's, on a veined slab) bends; so the straight edges seen entering and leaving the hole are drawn through it
first (engine.inpaint.straight_edges), and each side of them is filled from its own side of the border only.
"""

from __future__ import annotations

import cv2
import numpy as np

from engine.inpaint.coarse import grown_box
from engine.inpaint.registry import Inpainter, register
from engine.inpaint.straight_edges import crossing_lines, normalised_blur, side_labels

EPS = 5  # px: the neighbourhood a pixel is filled from
KAPPA = 25.0  # how strongly the weights follow the edge direction where it is clear
SIGMA = 1.4  # px: the smoothing before the gradients
RHO = 4.0  # px: the structure tensor's averaging
MARGIN = EPS + 3 * int(np.ceil(RHO + SIGMA))  # px of known image around the hole that the fill can read
LUMA = np.array([0.299, 0.587, 0.114], np.float32)


def _offsets() -> tuple[np.ndarray, np.ndarray]:
    """(K, 2) integer offsets (dy, dx) within EPS px but the centre, and their lengths."""
    dy, dx = np.mgrid[-EPS:EPS + 1, -EPS:EPS + 1]
    r = np.hypot(dy, dx)
    keep = (r > 0) & (r <= EPS)
    return np.stack([dy[keep], dx[keep]], 1), r[keep].astype(np.float32)


def _across_edges(grey: np.ndarray, known: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per pixel the unit direction (ux, uy) across the edges of `grey` (the structure tensor's major
    eigenvector: the edges run perpendicular to it), and its coherence in [0, 1] (((l1 - l2) / (l1 + l2))
    squared). The tensor is read off the `known` pixels only and carried into the rest by a normalised mean
    over `reach` px, once: a tensor recomputed from the fill as it grows mixes the two edges of a band where
    they near each other, and the band pinches."""
    k = known.astype(np.float32)
    smooth = normalised_blur(grey, k, SIGMA)
    gy, gx = np.gradient(smooth)
    trusted = cv2.erode(k, np.ones((3, 3), np.uint8))  # no gradient across the unknown's placeholder
    products = np.stack([gx * gx, gx * gy, gy * gy], -1)
    tensor = normalised_blur(products, trusted, RHO)
    far = normalised_blur(products, trusted, max(RHO, reach))
    tensor = np.where(known[..., None], tensor, far)
    jxx, jxy, jyy = tensor[..., 0], tensor[..., 1], tensor[..., 2]
    root = np.sqrt((jxx - jyy) ** 2 + 4 * jxy ** 2)
    coherence = (root / np.maximum(jxx + jyy, 1e-12)) ** 2
    theta = 0.5 * np.arctan2(2 * jxy, jxx - jyy)
    return np.cos(theta), np.sin(theta), np.clip(coherence, 0.0, 1.0)


def coherence_fill(image: np.ndarray, mask: np.ndarray, low_pass: float = 0.0) -> np.ndarray:
    """`image` (H, W, C) float32 in 0-255 with `mask` (H, W) filled by coherence transport (module docstring); a
    mask over every pixel leaves nothing to carry, and the image is returned as it is. The straight edges that
    cross the hole (engine.inpaint.straight_edges) are drawn through it: each side of them is filled from its own
    side of the border only, and what no side's border reaches from the whole border after. With `low_pass`
    (px) the colours carried are the known pixels' Gaussian mean at that sigma; the known pixels stay as they are."""
    known = ~mask
    if not known.any():
        return image.astype(np.float32)
    source = normalised_blur(image.astype(np.float32), known.astype(np.float32), low_pass) if low_pass > 0 else image
    work = np.where(mask[..., None], 0.0, source).astype(np.float32)
    grey = work @ LUMA if work.shape[-1] == 3 else work.mean(-1)
    reach = float(cv2.distanceTransform(mask.astype(np.uint8), cv2.DIST_L2, 5).max())
    direction = _across_edges(grey, known, reach)
    lines = crossing_lines(grey / 255.0, mask)
    labels = side_labels(lines, mask.shape)
    done = np.zeros_like(mask)
    for label in np.unique(labels[mask]) if lines else []:
        done |= _transport(work, mask & (labels == label), known & (labels == label), direction)
    _transport(work, mask & ~done, known | done, direction)
    return np.where(mask[..., None], work, image).astype(np.float32)


def _transport(work: np.ndarray, fill: np.ndarray, readable: np.ndarray,
               direction: tuple[np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """Fills `work`'s `fill` pixels in place from its `readable` ones (and those filled before them), one layer
    of the distance to `readable` at a time; returns the pixels filled (one with nothing readable within EPS px
    of it when its layer comes is left)."""
    ux, uy, coherence = direction
    readable = readable.copy()
    filled = np.zeros_like(fill)
    if not fill.any() or not readable.any():
        return filled
    layer = np.ceil(cv2.distanceTransform((~readable).astype(np.uint8), cv2.DIST_L2, 5)).astype(int)
    offsets, lengths = _offsets()
    h, w = fill.shape
    for level in np.unique(layer[fill]):
        ys, xs = np.nonzero(fill & (layer == level))
        ny, nx = ys[:, None] + offsets[:, 0], xs[:, None] + offsets[:, 1]
        inside = (ny >= 0) & (ny < h) & (nx >= 0) & (nx < w)
        ny, nx = np.clip(ny, 0, h - 1), np.clip(nx, 0, w - 1)
        across = offsets[:, 1] * ux[ys, xs][:, None] + offsets[:, 0] * uy[ys, xs][:, None]  # off the edge line
        mu = KAPPA * coherence[ys, xs][:, None]
        usable = inside & readable[ny, nx]
        weight = np.exp(-0.5 * (mu / EPS) ** 2 * across ** 2) / lengths * usable
        weight = np.where(weight.sum(1, keepdims=True) > 1e-6, weight, usable / lengths)
        reached = weight.sum(1) > 0
        weight /= np.maximum(weight.sum(1, keepdims=True), 1e-12)
        ys, xs = ys[reached], xs[reached]
        work[ys, xs] = np.einsum("pk,pkc->pc", weight[reached], work[ny[reached], nx[reached]])
        readable[ys, xs] = True
        filled[ys, xs] = True
    return filled


@register("coherence")
class CoherenceTransport(Inpainter):
    """Numpy on the hole's neighbourhood, one distance layer at a time; a hole above max_hole_px is filled
    downscaled (engine.inpaint.coarse) as Telea's is, where a smooth fill loses nothing."""

    summary = "coherence transport: smooth fill from the border along the image's edges"
    max_hole_px = 20_000
    low_pass: float = 0.0  # px: the sigma of the Gaussian mean of the known colours carried in (0: as they are)

    def parallel_views(self) -> str:
        return "threads"

    def inpaint_rgb(self, image: np.ndarray, mask: np.ndarray, prompt: str | None) -> np.ndarray:
        rows, cols = grown_box(mask, lambda extent: MARGIN)
        out = image.copy()
        filled = coherence_fill(image[rows, cols].astype(np.float32), mask[rows, cols], self.low_pass)
        out[rows, cols] = np.clip(np.rint(filled), 0, 255).astype(np.uint8)
        return out


@register("coherence-smooth")
class SmoothCoherenceTransport(CoherenceTransport):
    """Coherence transport of the border's colours low-passed (a Gaussian mean of the known pixels, sigma
    `low_pass` px): the border's pixel-scale grain and the dark rim where a removed render softens at the hole are
    not drawn into the hole as they are. Why: on a plain wall the fill scored below the flat patch `remove` lays
    (GPU wallmount_s8 at 4350d6a, Ref-coherence 34.26 dB unbiased against the patch's 35.19). 2D on six tuning
    scenes, grown 13 px: 25.18 dB against coherence's 25.05 (sigma 3: 25.39, but the livingroom's falls further;
    `docs/results/cpu/fill_2d.json` coherence_grow_13). Not the default: as Ref's fill on tiny CPU runs of the four
    tuning scenes, on the same removals, -0.08 / -1.34 / -0.33 / +0.55 dB (statue_s55, tabletop_s8, livingroom_s8,
    wallmount_s8; the tabletop's dark contact rim spread into the hole), -0.60/+0.13/-0.17 on the default-path scene
    (`decisions/cpu_tiny_runs.json`, coherence_smooth_1314729)."""

    summary = "coherence transport of the border's colours low-passed: no pixel grain carried into the hole"
    low_pass = 1.5
