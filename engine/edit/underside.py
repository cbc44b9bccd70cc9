"""The support under the object's footprint that the views built off its plane, repainted in the colour of the lit
support around it.

Where an object overhangs its support (a snowman's ball over a table), the views saw the support under it only at
grazing angles and in the object's shade, so 3DGS built it as a crater: Gaussians below the plane (tiny livingroom:
median 0.09 of the footprint's radius below it, a tenth of them beyond 0.37) and dark. After removal every view that
looks under where the object stood sees them as a dark ring, which the relights do not mend: they scale a colour
that is a shaded copy of the support's, and this one is what grazing views made of it (lifting those Gaussians onto
the plane made it worse, docs/BENCHMARKS.md). The support's own colour is known from around the object, after the
relights: the trimmed mean base colour of the support's Gaussians in a ring just beyond the footprint (RING x its
radius). The Gaussians under the footprint (within `underside_reach` x its radius of the object's axis, in the
relights' band about the plane) and off the plane by more than OFF_PLANE x the radius take it, without their
view-dependent terms. On the plane the support was built where views saw it well, so its texture stays.
Why a mean and not the median: a flat colour scores best at the texture's mean, and on wood of light and dark
stripes the per-channel median is the majority stripe's colour (the GPU livingroom's crater G +0.15 over gt/'s);
the mean gave that scene's unfilled hole 19.11 -> 21.41 dB (docs/BENCHMARKS.md, "Removal and its effects").
By default (`remove --seen-colour`) the ring's colour is what the training views render of it instead (seen_ring):
at full size the base colours' mean counts Gaussians under the surface that no view sees, and the GPU judges found
it off gt/'s ring by up to 0.154 (a pink patch on a wall) where the views' colour was within 0.034.

Where the views built no support at all under the object (a toy on a cloth: the cloth under it was hidden in most
views, so after removal the render sees through to the table below), a patch is laid (`find_unbuilt`): one flat
Gaussian of the same colour on the plane in each cell of the object's footprint that the support's Gaussians cover
less than `unbuilt_cover` (0.9), so every view shows the support there rather than what lies beneath it; and
where the support was built but the training views see through it (`seen_through`: gaps between large Gaussians
from the side, the floor under a table showing as a dark disc where a ball stood).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch

from engine.base.knn import knn
from engine.edit.effects import LUMA, EffectsConfig, Samples, colors_of, darker_share, support_only, trimmed_mean
from engine.edit.plane_grid import Site
from engine.formats.cameras import Camera, backproject, project, sample_nearest
from engine.formats.splat_ply import SH_C0
from engine.io.gaussians import PARAM_NAMES, Gaussians

Views = tuple[list[Camera], list[np.ndarray]]  # cameras and the depth each renders

RING = (1.0, 1.5)  # x the footprint's radius: the support whose colour the underside takes
OFF_PLANE = 0.02  # x the footprint's radius: off the plane by more than this, the support was built from grazing views
MIN_RING = 20  # Gaussians in the ring, for its colour
LAID_OPACITY = 0.95  # the patch's Gaussians
SOLID = 0.9  # a rendered pixel this opaque (3 px from any less) shows the support whole, not a faint rim over black
SEEN_BAND = 0.1  # x the footprint's radius: a view's surface point this near the plane shows the support
MIN_SEEN = 200  # the views' ring samples, for its colour (fewer: the Gaussians' base colours)
# a footprint cell whose rendered surface lies more than SEEN_BAND x the radius under the plane in at least this share
# of the training views that see it is seen through (find_unbuilt)
THROUGH_SHARE = 0.5


@dataclass
class Underside:
    """Which remaining Gaussians the underside repaint takes, and the colour it gives them."""

    painted: np.ndarray  # (N,) bool over the remaining Gaussians
    colour: np.ndarray  # (3,) base colour in [0, 1]
    # (S,) per painted Gaussian, 0 (not darker than the support around) to 1 (clearly darker): the effect masks'
    # share. The object's shade is an effect; a crater of the support's own colour is only a wrong depth
    weight: np.ndarray

    def report(self) -> dict:
        return {"painted_gaussians": int(self.painted.sum()), "clearly_darker": int((self.weight > 0.5).sum()),
                "colour": [round(float(c), 3) for c in self.colour]}


def find_underside(remaining: Gaussians, obj: np.ndarray, plane: tuple[np.ndarray, float] | None,
                   config: EffectsConfig, others: np.ndarray | None = None,
                   shown: Samples | None = None) -> Underside | None:
    """The Gaussians under the object (core centres `obj`) standing on `plane` that lie off it, and the colour
    of the support around (as the views' samples `shown` render it, where given); None where there are none, no
    plane, or too little support around to tell. Other objects' Gaussians (`others`) are neither painted nor part
    of the support around."""
    if plane is None or len(obj) < 20 or config.underside_reach <= 0:
        return None
    site = Site.of(obj, plane)
    means = remaining["means"].numpy()
    band, across, colour = _support_around(remaining, site, config, others, shown)
    painted = (band & (across < config.underside_reach * site.radius)
               & (np.abs(site.frame.height(means)) > OFF_PLANE * site.radius))
    if colour is None or not painted.any():
        return None
    colors = colors_of(remaining)
    darker = np.log(colour @ LUMA + 1e-3) - np.log(colors[painted] @ LUMA + 1e-3)
    return Underside(painted=painted, colour=colour, weight=darker_share(darker, config.min_contrast))


def _support_around(remaining: Gaussians, site: Site, config: EffectsConfig, others: np.ndarray | None,
                    shown: Samples | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """(N,) the support's Gaussians in the relights' band about the plane, (N,) each Gaussian's distance across
    the plane from the footprint's centre, and the support's colour in the ring just beyond the footprint: the
    trimmed mean of the views' samples `shown` there (seen_ring), else of the band's Gaussians' base colours there
    (None with fewer than MIN_RING)."""
    means = remaining["means"].numpy()
    band = support_only(site.near_plane(means, config.band_below), others)
    across = np.linalg.norm(site.frame.flat(means) - site.centre, axis=1)
    ring = band & (across > RING[0] * site.radius) & (across < RING[1] * site.radius)
    seen = None if shown is None else seen_ring(site, shown)
    if seen is not None:
        return band, across, seen
    if ring.sum() < MIN_RING:
        return band, across, None
    return band, across, trimmed_mean(colors_of(remaining)[ring])  # not medians: the ring's wood stripes


def seen_ring(site: Site, shown: Samples) -> np.ndarray | None:
    """The trimmed mean colour of the views' surface samples `shown` within SEEN_BAND of the plane in the ring
    just beyond the footprint; None with fewer than MIN_SEEN there. Why the views and not the Gaussians: a mean over
    the Gaussians counts the ones under the surface that no view sees, and their colours are whatever training left
    (GPU runs at 3067ef9 and 74fef3e: the base colours' mean 0.04 to 0.08 off gt/'s ring in some channel on six of
    seven scenes, wallmount_s101's pale pink plaque; tiny CPU livingroom_s8: R +0.023 against the views' -0.002)."""
    across = np.linalg.norm(site.frame.flat(shown.points) - site.centre, axis=1)
    ring = in_ring(site.frame.height(shown.points), across, site.radius)
    return trimmed_mean(shown.colors[ring]) if ring.sum() >= MIN_SEEN else None


def in_ring(height: np.ndarray, across: np.ndarray, radius: float) -> np.ndarray:
    """(P,) whether points `height` off the plane and `across` it from the footprint's centre lie in the ring
    (RING x the footprint's `radius`) within SEEN_BAND x it of the plane: where a view's sample shows the support."""
    return (np.abs(height) < SEEN_BAND * radius) & (across > RING[0] * radius) & (across < RING[1] * radius)


def find_unbuilt(remaining: Gaussians, obj: np.ndarray, plane: tuple[np.ndarray, float] | None,
                 config: EffectsConfig, others: np.ndarray | None = None,
                 shown: Samples | None = None, views: Views | None = None) -> Gaussians | None:
    """A patch for the support never built under the object: one flat Gaussian on the plane, in the support's
    colour around, per cell of the object's footprint (seen from straight above) that the support's Gaussians
    cover with less than `config.unbuilt_cover` opacity, or, given the training `views` (cameras and the depth they
    render of `remaining`), that they see through (seen_through); None where every cell is covered, or as
    find_underside. Each takes the identity of the support Gaussian nearest it. Why: removal otherwise shows what lies
    under the support there (a tiny CPU tabletop of seed 90: the table's wood through the cloth; removal outside the
    true hole 26.56 -> 28.25 dB, the unfilled hole 15.19 -> 22.93, Ref-telea 23.17 -> 23.97)."""
    if plane is None or len(obj) < 20 or config.underside_reach <= 0:
        return None
    site = Site.of(obj, plane)
    band, _, colour = _support_around(remaining, site, config, others, shown)
    if colour is None:
        return None
    grid, frame = site.grid, site.frame
    cells = np.argwhere(grid.raster(frame.flat(obj), site.spacing))
    centres = grid.origin + (cells + 0.5) * grid.cell
    bare = _cover(remaining, band, frame.flat, centres, grid.cell) < config.unbuilt_cover
    points = frame.point(centres)
    if views is not None:
        bare |= seen_through(site, points, *views) >= THROUGH_SHARE
    if not bare.any():
        return None
    return _flat_patch(remaining, points[bare], frame, grid.cell, colour, band)


def seen_through(site: Site, points: np.ndarray, cameras: list[Camera], depths: list[np.ndarray]) -> np.ndarray:
    """(C,) for `points` on the plane, the share of the `cameras` seeing each (in frame, in front, not hidden by a
    surface standing over the plane) whose rendered surface there (`depths`) lies more than SEEN_BAND x the footprint's
    radius under the plane; 0 where none sees it. Why views and not the cover from above (_cover): the support under
    a ball is built of large Gaussians, part of them well under the plane, that cover every cell seen from above and
    still leave gaps between them from the side; the views see the floor under the table through them, a dark disc
    in every view (tiny CPU livingroom_s8: removed 11-19 levels under gt/ within 0.8 footprint radii, a fifth of that
    from the floor; the GPU's livingroom_s8 laid no patch at all, its disc stayed)."""
    tol = SEEN_BAND * site.radius
    under = np.zeros(len(points))
    seeing = np.zeros(len(points))
    for camera, depth in zip(cameras, depths, strict=True):
        u, v, z = project(camera, points)
        rendered, inside = sample_nearest(depth, u, v)
        ok = inside & (z > 0) & np.isfinite(rendered) & (rendered > 0)
        height = np.full(len(points), np.inf)
        height[ok] = site.frame.height(backproject(camera, u[ok], v[ok], rendered[ok]))
        ok &= height < tol  # nothing of another surface in front
        seeing += ok
        under += ok & (height < -tol)
    return np.where(seeing > 0, under / np.maximum(seeing, 1), 0.0)


def _cover(remaining: Gaussians, band: np.ndarray, flat, centres: np.ndarray, cell: float) -> np.ndarray:
    """(C,) how opaque the `band` Gaussians make each in-plane point `centres` seen from above: 1 - the product of
    (1 - opacity x falloff), each Gaussian's falloff a normal in its distance over its largest scale (a cell at
    least)."""
    sigma = np.maximum(np.exp(remaining["scales"].numpy()).max(1), cell)
    across = flat(remaining["means"].numpy())
    middle = centres.mean(0)  # only those that reach the footprint: the band spans three object heights around it
    reach = np.linalg.norm(centres - middle, axis=1).max() + 3.0 * sigma
    near = band & (np.linalg.norm(across - middle, axis=1) < reach)
    opacity = torch.sigmoid(remaining["opacities"]).numpy().reshape(-1)[near]
    sigma, across = sigma[near], across[near]
    cover = np.zeros(len(centres))
    for start in range(0, len(centres), 256):
        d = np.linalg.norm(centres[start:start + 256, None] - across[None], axis=-1) / sigma[None]
        alpha = np.where(d < 3.0, opacity[None] * np.exp(-0.5 * d ** 2), 0.0)
        cover[start:start + 256] = 1.0 - np.prod(1.0 - np.clip(alpha, 0.0, 0.99), axis=1)
    return cover


def _flat_patch(remaining: Gaussians, points: np.ndarray, frame, cell: float, colour: np.ndarray,
                band: np.ndarray) -> Gaussians:
    """Gaussians at `points` on the plane, a cell wide and a tenth of one thick, of base `colour` seen alike from
    every side, each with the identity of the nearest `band` Gaussian."""
    n = len(points)
    support = np.flatnonzero(band)
    _, ids = knn(torch.as_tensor(points, dtype=torch.float32), remaining["means"][torch.as_tensor(support)], 1)
    nearest = torch.as_tensor(support)[ids[:, 0]]
    patch = {k: remaining[k][nearest].clone() for k in PARAM_NAMES}
    patch["means"] = torch.as_tensor(points, dtype=torch.float32)
    patch["quats"] = torch.as_tensor(_quaternion(np.stack([frame.a, frame.b, frame.n], 1)),
                                     dtype=torch.float32).repeat(n, 1)
    patch["scales"] = torch.log(torch.tensor([cell, cell, cell / 10], dtype=torch.float32)).repeat(n, 1)
    patch["opacities"] = torch.full((n,), math.log(LAID_OPACITY / (1 - LAID_OPACITY)))
    patch["sh0"] = torch.as_tensor((colour - 0.5) / SH_C0, dtype=torch.float32)[None, None].repeat(n, 1, 1)
    patch["shN"] = torch.zeros_like(patch["shN"])
    return patch


def _quaternion(rotation: np.ndarray) -> list[float]:
    """(w, x, y, z) of a proper rotation matrix whose columns are the local axes (the plane's a, b and n)."""
    m = rotation
    w = math.sqrt(max(1.0 + m[0, 0] + m[1, 1] + m[2, 2], 0.0)) / 2
    if w > 1e-3:
        return [w, (m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w), (m[1, 0] - m[0, 1]) / (4 * w)]
    axis = np.sqrt(np.clip((np.diag(m) + 1.0) / 2.0, 0.0, 1.0))  # a half turn: signs from the off-diagonals
    axis[1] *= 1.0 if m[0, 1] + m[1, 0] >= 0 else -1.0
    axis[2] *= 1.0 if m[0, 2] + m[2, 0] >= 0 else -1.0
    return [0.0, *axis.tolist()]


def paint(gaussians: Gaussians, underside: Underside) -> Gaussians:
    """The Gaussians with the underside's ones in its colour, seen alike from every side."""
    out = dict(gaussians)
    idx = torch.from_numpy(np.flatnonzero(underside.painted))
    sh0, sh_n = gaussians["sh0"].clone(), gaussians["shN"].clone()
    sh0[idx, 0] = torch.as_tensor((underside.colour - 0.5) / SH_C0, dtype=sh0.dtype)
    sh_n[idx] = 0.0
    out["sh0"], out["shN"] = sh0, sh_n
    return out
