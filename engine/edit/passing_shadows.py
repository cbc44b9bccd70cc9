"""Shadows that pass through the object's: darkness its cast shadow lies in that runs on past it.

Why: the generated statue stands on a slab under trees whose trunks reach far out of every view; their shadows
are long bands across the slab along the sun's direction, and on a held-out scene (statue_s100) one such band
crossed where the statue's shadow fell. The trees' Gaussians stop where the views stop, so their own cast
(effects.their_shadows) never reaches the slab; the band inside the statue's shadow was relit with it, and every
completion then painted a lit slab where the truth keeps the band (Ref-telea 14.01 dB m-PSNR in the hole against
21.53 for the unfilled hole). What the views show says it instead: the object's own shadow ends where the object
stops blocking the light, so along the light's direction across the plane it is lit just past both of its ends (past
the tip, and on the object's sunlit side); a band from elsewhere is dark on past them.

Two uses: `band_lines` keeps such bands out of the light's search (a band along the light rewards a longer
cast, so a low sun won), `passing_shadows` keeps them dark once the light is found.
"""

from __future__ import annotations

import numpy as np

from engine.edit.plane_grid import PlaneFrame, PlaneGrid, grown, pooled_sums

WINDOW = 8  # cells past the object's cast (and the plane under it) whose samples say whether the darkness runs on
POOL = 3  # each cell speaks for the samples of the POOL x POOL cells around it outside the cast (a cell holds ~1)
LINE_DEPTH, LINE_POOL = 4, 5  # band_lines: cells past the object's sunlit side, and lines pooled across
MIN_SAMPLES = 8  # a side with fewer samples in its window says nothing
DARK_SHARE = 0.5  # a side counts as dark at half the shadow's own contrast or more (a two-tone texture: ~0.1 of it)


def passing_shadows(grid: PlaneGrid, frame: PlaneFrame, light: np.ndarray, cast: np.ndarray, under: np.ndarray,
                    flat: np.ndarray, contrast: np.ndarray, shadow_contrast: float, ring: int = 0) -> np.ndarray:
    """(size, size) bool: the cells of the object's `cast` (and of the `ring` cells around it, where its lit edge
    is measured) whose darkness runs on past the cast along the light's direction across the plane: dark on both
    sides. Not one dark side with nothing known on the other (off the support): under a snowman's overhang, past
    its base on the sunlit side, the floor is dark and its shadow's tip lay off the samples (tiny CPU livingroom:
    42 of the shadow's Gaussians left dark, -0.5 dB outside the hole).

    `under`: the plane under the object (walked through with the cast: what lies under it is neither the
    shadow's end nor lit past it); `flat`: (P, 2) the views' samples on the plane; `contrast`: (P,) how much
    darker each is than the lit surface (log-luminance); `shadow_contrast`: the object's shadow's own. A side is
    dark where its samples' mean contrast reaches DARK_SHARE of the shadow's: a shadow from the same sun is as
    dark as the object's, a texture's dark patches average out with its light ones. Limit: a band as wide as two
    thirds of the shadow pulls the light's search (effects.find_shadow) to a low sun whose cast runs off the
    support, and then nothing past its tip says the darkness runs on."""
    u = _across(frame, light)
    if u is None or not cast.any():
        return np.zeros_like(cast)
    blocked = cast | under
    count, total = _per_cell(grid, flat, contrast, blocked)
    cells = np.argwhere(grown(cast, ring) & ~under)
    sides = [_side(cells, sign * u, blocked, count, total, grid.size, shadow_contrast) for sign in (1.0, -1.0)]
    runs_on = sides[0] & sides[1]
    out = np.zeros_like(cast)
    out[cells[runs_on, 0], cells[runs_on, 1]] = True
    return out


def band_lines(frame: PlaneFrame, light: np.ndarray, obj_flat: np.ndarray, flat: np.ndarray, contrast: np.ndarray,
               cell: float, threshold: float) -> np.ndarray:
    """(P,) bool: the samples (`flat`, in-plane) on lines along the light's direction across the plane that are
    dark (mean `contrast` at least `threshold`) just past the object on its sunlit side, where its own shadow
    never falls. Such a line is a band from something farther towards the light (a tree out of view); for the
    light's search its samples say nothing, as they are dark whatever the elevation. Lines are LINE_DEPTH cells deep
    past the object and pooled LINE_POOL cells across."""
    u = _across(frame, light)
    if u is None:
        return np.zeros(len(flat), bool)
    v = np.array([-u[1], u[0]])
    edge = float((obj_flat @ u).max())
    along, across = flat @ u - edge, flat @ v
    lo = float(min((obj_flat @ v).min(), across.min()))
    line = np.floor((across - lo) / cell).astype(int)
    sunward = (along > cell) & (along <= (1 + LINE_DEPTH) * cell)
    bins = int(line.max()) + 1
    count = np.bincount(line[sunward], minlength=bins).astype(float)
    total = np.bincount(line[sunward], weights=contrast[sunward], minlength=bins)
    kernel = np.ones(LINE_POOL)
    count, total = np.convolve(count, kernel, "same"), np.convolve(total, kernel, "same")
    dark = (count >= MIN_SAMPLES) & (total >= threshold * np.maximum(count, 1.0))
    return dark[line]


def _across(frame: PlaneFrame, light: np.ndarray) -> np.ndarray | None:
    """The light's direction across the plane, a unit vector in its own coordinates; None for a light straight
    above it, which casts no direction."""
    u = frame.flat(light[None])[0]
    norm = float(np.linalg.norm(u))
    return None if norm < 1e-6 else u / norm


def _per_cell(grid: PlaneGrid, flat: np.ndarray, contrast: np.ndarray, blocked: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Per cell, how many samples fall in the POOL x POOL cells around it and the sum of their contrasts, the
    `blocked` cells' own left out (the shadow's samples must not say that what lies past it is dark)."""
    ij, ok = grid.index(flat)
    ok &= ~blocked[np.clip(ij[:, 0], 0, grid.size - 1), np.clip(ij[:, 1], 0, grid.size - 1)]
    sums, counts = pooled_sums(grid.size, ij, contrast[:, None], ok, POOL)
    return counts, sums[..., 0]


def _side(cells: np.ndarray, direction: np.ndarray, blocked: np.ndarray, count: np.ndarray, total: np.ndarray,
          size: int, shadow_contrast: float) -> np.ndarray:
    """For each cell, walking along `direction` (in cells) out of `blocked`: whether the WINDOW cells past it
    hold samples enough to say, and are dark."""
    steps = np.arange(1, 2 * size + WINDOW)
    pos = np.floor(cells[:, None, :] + 0.5 + steps[None, :, None] * direction[None, None, :]).astype(int)
    on = ((pos >= 0) & (pos < size)).all(-1)
    at = np.clip(pos, 0, size - 1)
    inside = on & blocked[at[..., 0], at[..., 1]]
    first = np.argmax(~inside, axis=1)  # the first step out of the cast and what is under the object (or off the grid)
    window = first[:, None] + np.arange(WINDOW)[None, :]
    window = np.minimum(window, len(steps) - 1)
    w_on = np.take_along_axis(on, window, 1) & ~np.take_along_axis(inside, window, 1)
    wi, wj = np.take_along_axis(at[..., 0], window, 1), np.take_along_axis(at[..., 1], window, 1)
    n = (count[wi, wj] * w_on).sum(1)
    mean = (total[wi, wj] * w_on).sum(1) / np.maximum(n, 1.0)
    return (n >= MIN_SAMPLES) & (mean >= DARK_SHARE * shadow_contrast)
