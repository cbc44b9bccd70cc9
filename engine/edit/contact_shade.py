"""The darkening an object leaves on its support under and beside itself (the sky it hid: ambient
occlusion, the contact shadow), found without a light and undone by relighting.

The cast-shadow search (engine.edit.effects) finds what one light threw; what stays after it is softer:
strongest under an overhang, fading away from it. The views that saw the support under a snowman's ball
saw it dark, so the removed scene keeps a dark disc larger than the hole there (livingroom: with the
shadow's missed rim, about half of the error outside the hole). Found as a shading field on the plane:

1. The zone: the object's footprint seen from straight above, grown by `contact_reach` x its radius.
2. Each cell's shading is the mean log colour of the views' samples of the support (relit: after the cast
   shadow) within `window` cells; the reference is the same over the lit support just beyond the zone,
   from a window wide enough to reach it (so a cell on a pink mat is compared with the pink mat beside it).
   A texture finer than the window averages out of both, so what is left is the light it had.
   Where the darkness runs on past the zone, the reference is that darkness: darkening from the object fades
   within reach of it, and where the lit ring beyond is as dark in the same direction from the object,
   something else darkens there (a tree's band through the object) and gt/ keeps it (`_running_on`); the
   cells there are compared with the darkest of the ring in their direction (`_band_cells`), so the band
   stays and only what the object added to it goes. A band wider than the object leaves lit support straight
   out from it across the band, so a cell is also compared with the ends of the darkest line through it whose
   first ring cells on both sides are dark (`_lines_through`). Not the object's own cast shadow, whose rim its
   relight left, nor other objects and their shadows (tiny CPU livingroom s7: -0.23 dB if so).
3. Cells darker than their reference by more than `min_contrast` (log-luminance) are shaded; the support's
   Gaussians in them are multiplied by the ratio, per channel, blended in over one `min_contrast` so the
   edge leaves no seam, none past the lit level of the support around (`_ceilings`). Where the texture
   survived, it comes back as it was. Inside the hole the renders show whatever was left there, which is relit
   too; the hole masks hand it to the inpainters all the same.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from engine.edit.effects import LINEAR_EPS, LUMA, EffectsConfig, Samples, colors_of, darker_share, support_only
from engine.edit.plane_grid import Site, pooled_sums
from engine.io.gaussians import Gaussians
from engine.io.image_io import srgb_to_linear
from engine.io.masks import dilate

MIN_SAMPLES = 8  # per window, for a shading estimate
SECTORS = 16  # directions from the object in which the ring beyond the zone says whether the darkness runs on
LINES = 16  # directions of a line through a zone cell along which a band's darkness may run on past the zone
MIN_CELLS = 4  # a sector's ring cells with a shading estimate, at least, for it to say
BRIGHT = 90.0  # percentile of the lit support's Gaussians (by luminance) that a relit one may reach (_ceilings)


@dataclass
class ContactShade:
    """The darkening found: which remaining Gaussians it covers and how much each is brightened."""

    shaded: np.ndarray  # (N,) bool over the remaining Gaussians
    gains: np.ndarray  # (S, 3) per shaded Gaussian, >= 1
    weight: np.ndarray  # (S,) 0 (at the threshold) to 1 (clearly darker): the effect mask's share
    contrast: float  # the darkest cell's log-luminance below its reference
    later: list[float] = field(default_factory=list)  # the same, found again after each relight (joined)

    def report(self) -> dict:
        return {"shaded_gaussians": int(self.shaded.sum()), "clearly_darker": int((self.weight > 0.5).sum()),
                "max_gain": [round(float(g), 3) for g in self.gains.max(0)] if len(self.gains) else None,
                "contrast": round(self.contrast, 3), "contrast_after_relights": [round(c, 3) for c in self.later]}

    def joined(self, again: ContactShade, most: float) -> tuple[ContactShade, np.ndarray]:
        """This darkening (relit) and what was found `again` on the renders after relighting it, as one: the
        Gaussians of either, brightened by both gains but in all by at most `most` ** 2.4, with the larger share of
        the effect mask; and the (S, 3) gains still to apply to `again.shaded`. Why the bound: where the relight
        does not reach the dark pixels (Gaussians off the support drawing them) each round finds them as dark,
        and on a tiny run three rounds multiplied a cell's gain to 242."""
        weight, gains = np.zeros(len(self.shaded), np.float32), np.ones((len(self.shaded), 3))
        weight[self.shaded], gains[self.shaded] = self.weight, self.gains
        weight[again.shaded] = np.maximum(weight[again.shaded], again.weight)
        step = np.minimum(again.gains, most ** 2.4 / gains[again.shaded])
        gains[again.shaded] *= step
        shaded = self.shaded | again.shaded
        return ContactShade(shaded=shaded, gains=gains[shaded], weight=weight[shaded], contrast=self.contrast,
                            later=[*self.later, again.contrast]), step


def find_contact_shade(remaining: Gaussians, obj: np.ndarray, plane: tuple[np.ndarray, float] | None,
                       shown: Samples, config: EffectsConfig, window: int = 2,
                       others: np.ndarray | None = None, cast: np.ndarray | None = None
                       ) -> ContactShade | None:
    """The darkening under and beside the object (core centres `obj`) on `plane`, read off what the views
    `shown` of the support (the removed scene's renders, its object regions included, since what the views
    saw under an overhang shows there); None where nothing is darker than around it. A cell's gain is of light
    (linear values, as `brighten` applies it), at most `config.contact_most` ** 2.4 (sRGB values). Other objects'
    Gaussians (`others`) are never brightened. `cast` (bool over `remaining`, as `others`): the object's own cast
    shadow, already relit. Darkness past the zone where those lie, or the `others` (their own shadows included),
    is theirs: it says nothing of a band through the object (`_running_on`)."""
    if plane is None or len(obj) < 20:
        return None
    site = Site.of(obj, plane)
    frame, grid = site.frame, site.grid
    grow = max(1, round(config.contact_reach * site.radius / grid.cell))
    min_contrast, band_below = config.min_contrast, config.band_below
    points, colors = shown.points, shown.colors
    above = grid.raster(frame.flat(obj), site.spacing)
    zone = dilate(above, grow)
    beyond = dilate(above, 2 * grow) & ~zone
    support = site.near_plane(points, band_below)
    ij, on_grid = grid.index(frame.flat(points[support]))
    ij, shown_colors = ij[on_grid], colors[support][on_grid]
    lit = beyond[ij[:, 0], ij[:, 1]]

    def shading(log_c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # each cell's and its reference's
        return (_window_mean(grid.size, ij, log_c, np.ones(len(ij), bool), 2 * window + 1),
                _window_mean(grid.size, ij, log_c, lit, 2 * (2 * grow + window) + 1))

    local, reference = shading(np.log(shown_colors + 1e-3))  # found in sRGB values, as min_contrast is
    darker = (reference - local) @ LUMA / LUMA.sum()
    means = remaining["means"].numpy()
    theirs = np.zeros(len(means), bool)
    for part in (others, cast):
        if part is not None:
            theirs |= part
    ring = beyond & ~_explained(site, means[theirs], window)
    sector = _sectors(grid.size, np.argwhere(above).mean(0))
    runs_on = _running_on(darker, zone, ring, sector, min_contrast)
    band = _band_cells(local, ring, sector) if runs_on.any() else None
    if band is not None:
        darker = np.where(runs_on, (_sector_mean(local, band, sector) - local) @ LUMA / LUMA.sum(), darker)
    ends = _lines_through(darker, zone, ring, min_contrast)
    through = ends[0] >= 0
    if through.any():
        darker = np.where(through, (_line_level(local, ends) - local) @ LUMA / LUMA.sum(), darker)
    weight = np.where(zone & np.isfinite(darker), darker_share(darker, min_contrast), 0.0)
    if not (weight > 0.5).any():
        return None
    local, reference = shading(np.log(srgb_to_linear(shown_colors) + LINEAR_EPS))  # undone in linear ones
    if band is not None:
        reference = np.where(runs_on[..., None], _sector_mean(local, band, sector), reference)
    if through.any():
        reference = np.where(through[..., None], _line_level(local, ends), reference)
    gain = np.exp(weight[..., None] * np.nan_to_num(reference - local))
    gain = np.clip(cv2.blur(gain.astype(np.float32), (3, 3)), 1.0, config.contact_most ** 2.4)
    weight = cv2.blur(weight.astype(np.float32), (3, 3))
    band_of_plane = support_only(site.near_plane(means, band_below, site.reach_up(remaining)), others)
    shaded = band_of_plane.copy()
    shaded[shaded] = grid.cells(weight, frame.flat(means[shaded])) > 0
    flat = frame.flat(means[shaded])
    lit_support = band_of_plane.copy()
    lit_support[lit_support] = grid.cells(ring, frame.flat(means[lit_support]))
    colours = colors_of(remaining)
    gains = np.minimum(grid.cells(gain, flat), _ceilings(grid.cells(reference, flat), srgb_to_linear(colours[shaded]),
                                                         srgb_to_linear(colours[lit_support])))
    return ContactShade(shaded=shaded, gains=np.maximum(gains, 1.0), weight=grid.cells(weight, flat),
                        contrast=float(np.nanmax(np.where(zone, darker, np.nan))))


def _ceilings(reference: np.ndarray, colours: np.ndarray, lit: np.ndarray) -> np.ndarray:
    """(S, 3) the largest gain each shaded Gaussian (linear `colours`) may take: to its cell's lit level (`reference`,
    the mean log of linear values; none where NaN) times the lit support's spread, the BRIGHT percentile of its
    Gaussians' (`lit`, linear) luminance over their geometric mean. Why: a cell's gain lifts its mean, and a
    Gaussian already lit in a dark cell (one layer of a surface other layers darken) went past the lit floor:
    a pale ring round the contact (tuning livingroom_s90, H200 and tiny CPU). The spread keeps a texture's light
    texels."""
    luma = lit @ LUMA
    spread = 1.0
    if len(luma) >= MIN_SAMPLES:
        spread = float(np.percentile(luma, BRIGHT) / np.exp(np.log(luma + LINEAR_EPS).mean()))
    level = np.exp(np.where(np.isfinite(reference), reference, np.inf))
    return spread * level / (colours + LINEAR_EPS)


def _explained(site: Site, points: np.ndarray, window: int) -> np.ndarray:
    """(size, size) bool: the cells under `points` (other objects, the object's own relit cast shadow), grown by
    the shading `window`, whose darkness is theirs."""
    if not len(points):
        return np.zeros((site.grid.size, site.grid.size), bool)
    return dilate(site.grid.raster(site.frame.flat(points), site.spacing), window)


def _running_on(darker: np.ndarray, zone: np.ndarray, beyond: np.ndarray, sector: np.ndarray, min_contrast: float
                ) -> np.ndarray:
    """(size, size) bool: the `zone` cells in a direction from the object (`sector`, _sectors) whose ring
    `beyond` the zone is, on the mean, `min_contrast` darker than its reference too: darkness that runs on past
    the zone, which the object did not cast (held-out statue_s100: a tree's band through the statue, relit
    beside it as its contact shade once no cast shadow was found there). A direction whose ring holds too
    few estimates (off the support) says nothing."""
    known = beyond & np.isfinite(darker)
    count = np.bincount(sector[known], minlength=SECTORS)
    total = np.bincount(sector[known], weights=darker[known], minlength=SECTORS)
    dark = (count >= MIN_CELLS) & (total >= min_contrast * np.maximum(count, 1))
    return zone & dark[sector]


def _lines_through(darker: np.ndarray, zone: np.ndarray, ring: np.ndarray, min_contrast: float
                   ) -> np.ndarray:
    """(2, size, size) int: for each `zone` cell on a line (one of LINES directions) whose first `ring` cells past
    the zone on both sides are `min_contrast` darker than their reference, those two cells (flat indices) on the
    darkest such line; -1 where no line is. Why: a band wider than the object (a tree's shadow across a statue and
    its plinth) leaves lit floor past the zone straight out from the object across it, so `_running_on`'s
    direction from the object says the darkness ends there, and the band round the object was relit to the lit
    floor (held-out statue_s100, training seed 1 on an H100: 4,474 Gaussians of the band beside the statue relit
    by up to 3.4x, a lit bay in every view). Along the band, its darkness runs on past the zone at both ends."""
    size = darker.shape[0]
    cells = np.argwhere(zone)
    ends, best = np.full((2, len(cells)), -1), np.full(len(cells), -np.inf)
    if not len(cells):
        return np.full((2, size, size), -1)
    dark = (ring & np.isfinite(darker)).ravel()
    values = np.where(dark, darker.ravel(), -np.inf)
    steps = np.arange(1, 2 * size)
    for theta in np.arange(LINES) * np.pi / LINES:
        step = np.array([np.sin(theta), np.cos(theta)])
        found = []
        for sign in (1, -1):
            at = np.rint(cells[:, None] + sign * steps[None, :, None] * step).astype(int)  # (Z, T, 2)
            on = (at >= 0).all(-1) & (at < size).all(-1)
            flat = np.where(on, np.clip(at[..., 0], 0, size - 1) * size + np.clip(at[..., 1], 0, size - 1), 0)
            hit = on & dark[flat]
            first = flat[np.arange(len(cells)), hit.argmax(1)]
            found.append(np.where(hit.any(1), first, -1))
        score = np.where((found[0] >= 0) & (found[1] >= 0),
                         np.minimum(values[np.maximum(found[0], 0)], values[np.maximum(found[1], 0)]), -np.inf)
        better = score > best
        best = np.where(better, score, best)
        ends[:, better] = np.stack(found)[:, better]
    ends[:, ~(best >= min_contrast)] = -1
    out = np.full((2, size, size), -1)
    out[:, cells[:, 0], cells[:, 1]] = ends
    return out


def _line_level(values: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """(size, size, C): the mean of the `values` (size, size, C) at each cell's two line ends (`_lines_through`),
    NaN where it has none."""
    flat = values.reshape(-1, values.shape[-1])
    level = 0.5 * (flat[np.maximum(ends[0], 0)] + flat[np.maximum(ends[1], 0)])
    return np.where((ends[0] >= 0)[..., None], level, np.nan)


def _band_cells(local: np.ndarray, ring: np.ndarray, sector: np.ndarray, share: float = 25.0) -> np.ndarray:
    """(size, size) bool: in each direction from the object (`sector`, _sectors) whose `ring` beyond the zone
    holds at least MIN_CELLS shading estimates (`local`), the darkest `share` percent of them. Where darkness runs
    on past the zone (a tree's band through the object) their shading is the band's own level: what lies in the
    band is relit to it, not to the lit support beside the band. The darkest share, not all: a band narrower
    than a sector leaves lit cells in its ring."""
    known = ring & np.isfinite(local).all(-1)
    luma = local @ LUMA
    band = np.zeros_like(known)
    for k in range(SECTORS):
        cells = known & (sector == k)
        if cells.sum() >= MIN_CELLS:
            band |= cells & (luma <= np.percentile(luma[cells], share))
    return band


def _sector_mean(values: np.ndarray, cells: np.ndarray, sector: np.ndarray) -> np.ndarray:
    """(size, size, C): each cell's direction's (`sector`) mean of the `values` (size, size, C) over `cells`
    (NaN where that direction has none)."""
    count = np.bincount(sector[cells], minlength=SECTORS)
    sums = np.stack([np.bincount(sector[cells], weights=values[cells][:, c], minlength=SECTORS)
                     for c in range(values.shape[-1])], -1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return (sums / count[:, None])[sector]


def _sectors(size: int, centre: np.ndarray) -> np.ndarray:
    """(size, size) each cell's direction from `centre` (in cells), one of SECTORS."""
    ii, jj = np.mgrid[0:size, 0:size]
    return (np.floor((np.arctan2(ii - centre[0], jj - centre[1]) + np.pi) / (2 * np.pi) * SECTORS).astype(int)
            % SECTORS)


def _window_mean(size: int, ij: np.ndarray, values: np.ndarray, use: np.ndarray, width: int) -> np.ndarray:
    """(size, size, C) mean of the `values` (M, C) of samples in cells `ij` that `use` over a window `width`
    cells wide around each cell; NaN where it holds fewer than MIN_SAMPLES."""
    sums, counts = pooled_sums(size, ij, values, use, width)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where((counts >= MIN_SAMPLES)[..., None], sums / counts[..., None], np.nan)
