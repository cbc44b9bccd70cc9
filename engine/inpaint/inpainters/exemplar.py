"""Exemplar-based inpainting (Criminisi, Perez and Toyama 2004): texture synthesis by copying patches.

Why our own: the benchmark asks whether a smooth inpainter (Telea, Navier-Stokes) beats a texture-synthesis
one in 3D, and OpenCV's texture-synthesis inpainter (xphoto's shift-map) is only in the contrib build,
which the GPU machine does not have and whose wheel (69 MB) does not fit a device transfer. This one needs
only numpy and OpenCV's core, on the CPU.

The algorithm, as published: the fill front is ordered by priority = confidence x data term (how strongly
an isophote flows into the hole, so linear structures are continued first); the front pixel of highest
priority takes the patch from the known region around the hole that best matches its known pixels (sum
of squared differences), copies it into its unknown pixels, and passes its confidence on to them. Source
patches come from the originally known pixels within a window around the hole (the hole's bounding box
grown by its own size, at least WINDOW_MARGIN px); the search over them is a correlation of that window with
the target patch (_SourceSearch).
"""

from __future__ import annotations

import cv2
import numpy as np

from engine.inpaint.coarse import coarse_view, grown_box
from engine.inpaint.registry import Inpainter, register

PATCH = 9  # px, odd: the published default
WINDOW_MARGIN = 48  # px around the hole's bounding box at least
MAX_HOLE_PX = 6000  # a larger hole picks its patches downscaled (exemplar_large)


def _window(mask: np.ndarray, half: int) -> tuple[slice, slice]:
    return grown_box(mask, lambda extent: max(WINDOW_MARGIN, extent) + half)


def _data_term(grey: np.ndarray, known: np.ndarray) -> np.ndarray:
    """|isophote . front normal| per pixel: the image gradient turned 90 degrees, against the mask's normal."""
    gx = cv2.Sobel(grey, cv2.CV_32F, 1, 0, ksize=3)
    gy = cv2.Sobel(grey, cv2.CV_32F, 0, 1, ksize=3)
    # gradients that straddle the unknown region are artefacts of its placeholder values
    trusted = cv2.erode(known.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    gx, gy = gx * trusted, gy * trusted
    # a front pixel is unknown, so it takes the gradient of its 3x3 neighbourhood (largest plus most negative)
    gx = cv2.dilate(gx, np.ones((3, 3), np.uint8)) + cv2.erode(gx, np.ones((3, 3), np.uint8))
    gy = cv2.dilate(gy, np.ones((3, 3), np.uint8)) + cv2.erode(gy, np.ones((3, 3), np.uint8))
    filled = known.astype(np.float32)
    nx = cv2.Sobel(filled, cv2.CV_32F, 1, 0, ksize=3)
    ny = cv2.Sobel(filled, cv2.CV_32F, 0, 1, ksize=3)
    norm = np.sqrt(nx * nx + ny * ny) + 1e-6
    return np.abs(-gy * nx / norm + gx * ny / norm) / 255.0 + 1e-3


def _priority(work: np.ndarray, unknown: np.ndarray, confidence: np.ndarray, patch: int) -> np.ndarray:
    """Confidence x data term on the fill front, -1 elsewhere, for any rectangle of the window."""
    known = ~unknown
    front = unknown & (cv2.dilate(known.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0)
    conf = cv2.boxFilter(confidence, -1, (patch, patch), normalize=True, borderType=cv2.BORDER_CONSTANT)
    pixels = work.astype(np.uint8)
    grey = (cv2.cvtColor(pixels, cv2.COLOR_RGB2GRAY) if work.shape[2] == 3 else pixels[..., 0]).astype(np.float32)
    return np.where(front, conf * _data_term(grey, known), -1.0)


def exemplar_fill(image: np.ndarray, mask: np.ndarray, patch: int = PATCH) -> np.ndarray:
    """Fill `mask` (True = unknown) of a uint8 (H, W, 3) image, or (H, W, 1) grey; returns a new image."""
    return exemplar_sources(image, mask, patch)[0]


def exemplar_sources(image: np.ndarray, mask: np.ndarray, patch: int = PATCH) -> tuple[np.ndarray, np.ndarray]:
    """exemplar_fill's image, and for every pixel of `mask` the (row, col) of the known pixel its colour was
    copied from ((H, W, 2) int, -1 outside the mask): what lets a coarse fill be copied again at full size.

    Filling a patch changes the priority only near it (within the patch's half width plus the 3x3
    filters of the data term), so after the first pass only that neighbourhood is recomputed, on a
    rectangle grown by the same reach again so that its edges see what the whole window would: the
    fill is the same as recomputing everything, and a hole of 30k pixels takes seconds, not minutes."""
    half = patch // 2
    reach = half + 3
    win_r, win_c = _window(mask, half)
    work = np.pad(image[win_r, win_c].astype(np.float32), ((half, half), (half, half), (0, 0)), mode="edge")
    unknown = np.pad(mask[win_r, win_c], half, mode="constant", constant_values=False)
    confidence = (~unknown).astype(np.float32)
    inside = np.pad(np.ones(mask[win_r, win_c].shape, bool), half, mode="constant", constant_values=False)
    search = _SourceSearch(work, inside & ~unknown, patch)
    h, w = unknown.shape
    source = np.full((h, w, 2), -1, np.int64)
    grid = np.stack(np.mgrid[0:h, 0:w], -1)
    priority = _priority(work, unknown, confidence, patch)
    left = int(unknown.sum())
    while left:
        r, c = np.unravel_index(int(np.argmax(priority)), priority.shape)
        r, c = min(max(r, half), h - half - 1), min(max(c, half), w - half - 1)
        rows, cols = slice(r - half, r + half + 1), slice(c - half, c + half + 1)
        fill = unknown[rows, cols].copy()
        sr, sc = search.best(work[rows, cols], ~fill)
        work[rows, cols][fill] = work[sr - half:sr + half + 1, sc - half:sc + half + 1][fill]
        source[rows, cols][fill] = grid[sr - half:sr + half + 1, sc - half:sc + half + 1][fill]
        confidence[rows, cols][fill] = confidence[rows, cols].sum() / patch ** 2
        unknown[rows, cols] &= ~fill
        left -= int(fill.sum())
        _update(priority, work, unknown, confidence, patch, (r, c), reach)
    out = image.copy()
    out[win_r, win_c] = np.clip(np.rint(work[half:-half, half:-half]), 0, 255).astype(np.uint8)
    where = np.full(image.shape[:2] + (2,), -1, np.int64)
    inner = source[half:-half, half:-half]
    offset = np.array([win_r.start - half, win_c.start - half])
    where[win_r, win_c] = np.where(inner >= 0, inner + offset, -1)
    return out, where


def exemplar_large(image: np.ndarray, mask: np.ndarray, max_hole_px: int, patch: int = PATCH) -> np.ndarray:
    """exemplar_fill for a hole of any size: above `max_hole_px` pixels the patches are chosen on the
    downscaled neighbourhood (engine.inpaint.coarse) and each full-size hole pixel copies the pixel at the
    same place within the scale x scale block its coarse pixel was copied from, so the texture comes back at
    full resolution; where that lands in the hole (the coarse source block straddled its edge) the coarse
    fill, upsampled, is used."""
    coarse = coarse_view(mask, max_hole_px)
    if coarse is None:
        return exemplar_fill(image, mask, patch)
    small, where = exemplar_sources(np.ascontiguousarray(coarse.down(image)), coarse.down_mask(mask), patch)
    out = coarse.up(small, image)
    ys, xs = np.nonzero(mask)
    s = coarse.scale
    cy, cx = (ys - coarse.rows.start) // s, (xs - coarse.cols.start) // s
    src = where[cy, cx]
    sy = coarse.rows.start + src[:, 0] * s + (ys - coarse.rows.start) % s
    sx = coarse.cols.start + src[:, 1] * s + (xs - coarse.cols.start) % s
    h, w = mask.shape
    ok = (src[:, 0] >= 0) & (sy < h) & (sx < w)
    ok[ok] &= ~mask[sy[ok], sx[ok]]
    out[ys[ok], xs[ok]] = image[sy[ok], sx[ok]]
    return out


def _update(priority: np.ndarray, work: np.ndarray, unknown: np.ndarray, confidence: np.ndarray, patch: int,
            centre: tuple[int, int], reach: int) -> None:
    """Recompute `priority` within `reach` of the patch at `centre`, from a rectangle twice as far out."""
    h, w = unknown.shape
    half = patch // 2
    inner = [(max(x - half - reach, 0), min(x + half + reach + 1, n)) for x, n in zip(centre, (h, w), strict=True)]
    outer = [(max(a - reach, 0), min(b + reach, n)) for (a, b), n in zip(inner, (h, w), strict=True)]
    o = tuple(slice(a, b) for a, b in outer)
    local = _priority(work[o], unknown[o], confidence[o], patch)
    (ia, ib), (ja, jb) = inner
    priority[ia:ib, ja:jb] = local[ia - outer[0][0]:ib - outer[0][0], ja - outer[1][0]:jb - outer[1][0]]


class _SourceSearch:
    """The source patch of least SSD over a target's known pixels, as a correlation of the window.

    sum_k w_k (s_k - t_k)^2 = sum_k w_k s_k^2 - 2 sum_k w_k t_k s_k + const over the 9x9 pixels (and channels)
    of every source centre is one correlation with a 9x9 kernel per channel and one more: the window's squared
    sum over channels with the known mask w, and each channel with -2 w t. For RGB that reads the window (H x W
    x 4 values) instead of a matrix of every source patch unrolled (H x W x 243): 4 ms a patch on one CPU core
    against 42 ms for the matrix, the same fills. Source patches are the originally known ones, which filling
    never changes, so the planes are set once. Why on the CPU: Exemplar.parallel_views
    (benchmarks/inpaint_speed.py)."""

    def __init__(self, work: np.ndarray, known: np.ndarray, patch: int) -> None:
        whole = cv2.erode(known.astype(np.uint8), np.ones((patch, patch), np.uint8),
                          borderType=cv2.BORDER_CONSTANT, borderValue=0) > 0
        planes = np.concatenate([(work * work).sum(2, keepdims=True), work], axis=2).transpose(2, 0, 1)
        self.planes = np.ascontiguousarray(planes, dtype=np.float32)  # (1 + C, H, W): sum of squares, channels
        self.penalty = np.where(whole, 0.0, np.inf).astype(np.float32)
        self.width = work.shape[1]

    def best(self, target: np.ndarray, target_known: np.ndarray) -> tuple[int, int]:
        """The (row, col) centre of the best source for `target` (patch, patch, C) over its known pixels."""
        w = target_known.astype(np.float32)
        kernels = np.concatenate([w[None], -2 * (w[..., None] * target).transpose(2, 0, 1)]).astype(np.float32)
        ssd = self.penalty.copy()
        for plane, kernel in zip(self.planes, kernels, strict=True):
            ssd += cv2.filter2D(plane, -1, kernel, borderType=cv2.BORDER_CONSTANT)
        return divmod(int(np.argmin(ssd)), self.width)


@register("exemplar")
class Exemplar(Inpainter):
    summary = "exemplar-based texture synthesis (Criminisi 2004), ours, on the CPU"

    def parallel_views(self) -> str:
        """Processes: a view is a Python loop of one patch at a time (seconds a 640x480 view on one core), so views
        go at once in processes, one a core. Not on the GPU: processes there wait on each other's GPU contexts and
        take the GPU from trainings beside (docs/BENCHMARKS.md, "Inpainting")."""
        return "processes"

    def inpaint_rgb(self, image, mask, prompt):
        return exemplar_large(image, mask, MAX_HOLE_PX)

    def inpaint_grey(self, grey, mask, prompt):
        """Depth as grey: one channel searched instead of three equal ones (two correlations a patch, not four),
        the same patches: three equal channels only triple every sum of squared differences."""
        return np.repeat(exemplar_large(np.ascontiguousarray(grey[..., :1]), mask, MAX_HOLE_PX), 3, axis=2)
