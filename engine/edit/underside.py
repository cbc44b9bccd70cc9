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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from engine.edit.effects import LUMA, EffectsConfig, colors_of, darker_share, support_only, trimmed_mean
from engine.edit.plane_grid import Site
from engine.formats.splat_ply import SH_C0
from engine.io.gaussians import Gaussians

RING = (1.0, 1.5)  # x the footprint's radius: the support whose colour the underside takes
OFF_PLANE = 0.02  # x the footprint's radius: off the plane by more than this, the support was built from grazing views
MIN_RING = 20  # Gaussians in the ring, for its colour


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
                   config: EffectsConfig, others: np.ndarray | None = None) -> Underside | None:
    """The Gaussians under the object (core centres `obj`) standing on `plane` that lie off it, and the colour
    of the support around; None where there are none, no plane, or too little support around to tell. Other
    objects' Gaussians (`others`) are neither painted nor part of the support around."""
    if plane is None or len(obj) < 20 or config.underside_reach <= 0:
        return None
    site = Site.of(obj, plane)
    means = remaining["means"].numpy()
    band = support_only(site.near_plane(means, config.band_below), others)
    across = np.linalg.norm(site.frame.flat(means) - site.centre, axis=1)
    ring = band & (across > RING[0] * site.radius) & (across < RING[1] * site.radius)
    painted = (band & (across < config.underside_reach * site.radius)
               & (np.abs(site.frame.height(means)) > OFF_PLANE * site.radius))
    if ring.sum() < MIN_RING or not painted.any():
        return None
    colors = colors_of(remaining)
    colour = trimmed_mean(colors[ring])  # not medians: the ring's wood stripes (effects.trimmed_mean)
    darker = np.log(colour @ LUMA + 1e-3) - np.log(colors[painted] @ LUMA + 1e-3)
    return Underside(painted=painted, colour=colour, weight=darker_share(darker, config.min_contrast))


def paint(gaussians: Gaussians, underside: Underside) -> Gaussians:
    """The Gaussians with the underside's ones in its colour, seen alike from every side."""
    out = dict(gaussians)
    idx = torch.from_numpy(np.flatnonzero(underside.painted))
    sh0, sh_n = gaussians["sh0"].clone(), gaussians["shN"].clone()
    sh0[idx, 0] = torch.as_tensor((underside.colour - 0.5) / SH_C0, dtype=sh0.dtype)
    sh_n[idx] = 0.0
    out["sh0"], out["shN"] = sh0, sh_n
    return out
