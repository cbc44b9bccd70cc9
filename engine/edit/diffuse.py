"""The support that the object hid from many training views, made diffuse once the object is gone.

A Gaussian of the floor (table, ground, wall) beside the object was trained only from the directions in which
the object did not stand in front of it. Its view-dependent colour (the SH bands above the DC term) fits those
directions and is unconstrained in the hidden ones, and removal opens exactly those: the views then see the
extrapolated terms, a ring darker or tinted than the support round it. The supports a removal meets are mostly
matte, so their DC term (the colour's mean over all directions) stands in for them from every side.

Which: the support's Gaussians within the object's reach that it hid from at least HIDDEN_SHARE of the training
views framing them; last in `remove`, after the effects (before them it changed what they read: tiny CPU
statue_s6's unfilled hole -0.19 dB). Tiny CPU runs (32 views, 1,500 steps), against gt/ on the test views, without
/ with it: removal outside the true hole statue_s6 32.10 / 32.19 dB, livingroom_s7 30.07 / 30.16; the revealed
part 25.39 / 25.75, 29.20 / 29.28; Ref-telea's m-PSNR 19.78 / 19.76, 28.10 / 28.29. On livingroom_s7 the bands
dropped on the whole support within reach instead (10,545 Gaussians, not 2,086) lose 0.30 dB outside the hole:
far from the object they carry real view-dependence; setting the DC term to the mean colour the seeing views saw
loses 0.07 (the sphere's mean extrapolates better than the seen directions' mean).
"""

from __future__ import annotations

import numpy as np
import torch

from engine.edit.effects import EffectsConfig, support_only
from engine.edit.plane_grid import Site
from engine.formats.cameras import Camera, project, sample_nearest
from engine.io.gaussians import Gaussians

FRONT_PERCENTILE = 2.0  # the object's nearest part in a view: this percentile of its core's camera depths
HIDDEN_SHARE = 0.2  # hidden from at least this share of the training views that frame a Gaussian: made diffuse


def hidden_share(means: np.ndarray, cameras: list[Camera], regions: list[np.ndarray], core: np.ndarray,
                 views: list[int]) -> np.ndarray:
    """(N,) per centre, the share of `views` framing it (in the frame, in front of the camera) in which the object
    hid it: inside the object's region there and behind the object's nearest part (`core`'s depths)."""
    framed, hidden = np.zeros(len(means)), np.zeros(len(means))
    for i in views:
        u, v, z = project(cameras[i], means)
        in_region, in_frame = sample_nearest(regions[i], u, v)
        depths = project(cameras[i], core)[2]
        front = np.percentile(depths[depths > 0], FRONT_PERCENTILE) if (depths > 0).any() else np.inf
        framed += in_frame & (z > 0)
        hidden += in_frame & in_region.astype(bool) & (z > front)
    return hidden / np.maximum(framed, 1)


def diffuse_support(gaussians: Gaussians, core: np.ndarray, plane: tuple[np.ndarray, float] | None,
                    cameras: list[Camera], regions: list[np.ndarray], views: list[int], others: np.ndarray | None,
                    config: EffectsConfig) -> tuple[Gaussians, int]:
    """`gaussians` with the support's Gaussians in the object's reach (the band the contact shade relights) that
    it hid from at least HIDDEN_SHARE of the training `views` made diffuse (their view-dependent bands zeroed),
    and how many. Other objects keep theirs (a glossy mug is glossy from every side)."""
    if plane is None or len(core) < 20 or gaussians["shN"].shape[1] == 0:
        return gaussians, 0
    site = Site.of(core, plane)
    means = gaussians["means"].numpy()
    rows = np.flatnonzero(support_only(site.near_plane(means, config.band_below, site.reach_up(gaussians)), others))
    rows = rows[hidden_share(means[rows], cameras, regions, core, views) >= HIDDEN_SHARE]
    if not len(rows):
        return gaussians, 0
    out = dict(gaussians)
    out["shN"] = gaussians["shN"].clone()
    out["shN"][torch.from_numpy(rows)] = 0
    return out, len(rows)
