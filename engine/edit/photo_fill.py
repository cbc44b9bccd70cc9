"""What the photos showed, for the hole pixels some photo saw: the inpainters invent only what no photo saw.

Why: `holes` marks more than the unseen part (3DGIC's "what no view saw behind the object"). It also marks what the
removed render shows wrongly: the support that the base run never built under the object, seen through; a crater
off its plane; the band whose render the photos contradict (engine.edit.border); and `inpaint` grows every mask by a
few pixels, since a render blurs a hole's edge. Some training photo saw each of those points, so their colour is
known: an inpainter given them invents it instead (on the held-out table the masks as inpainted were 2-8 times the
true hole, IoU 0.08-0.74, where the unseen part alone reached 0.77-0.97), and it reads the hole's colours from a
border that is itself wrong.

So `holes` writes, beside each mask, the photos' colour of every pixel within PHOTO_SHARE of the width of the hole
(the hole included) that is not unseen: the surface point there (the removed render's depth, stopped at the support
plane where the ray saw through it) looked up in every training photo that sees it, with the holes' own visibility
test (engine.io.visibility.visible_from: in frame, in front, not behind that view's removed surface, not in its
object region grown by engine.edit.border.OCCLUDER_SHARE, whose edge blends into the pixels beside it) and not in
the object's shadow in that photo (removed/effects: the shadow went with the object, the photos still show it); the
median of those photos per channel, so that one photo's misregistered edge does not decide. `inpaint` pastes those
colours and gives its inpainter the rest (`invented`).

Off by default (`holes --photo-band PHOTO_SHARE` turns it on): on the default path's own scene (livingroom seed 11,
96 px, 16 views) the photos' colours in the pasted pixels were 18.7 levels off the truth on the mean where the removed
render was 12.2 (the surface point misplaced by a coarse depth; the object's edge and shadow outside the identity
render's region), and the default fill fell from 31.71 to 24.03 dB m-PSNR against 30.22 unfilled.
"""

from __future__ import annotations

import numpy as np
import torch

from engine.base.device import pick_device
from engine.formats.cameras import Camera, backproject, pixel_grid
from engine.io.visibility import Array, as_tensor, sample_pixels, visible_from

PHOTO_SHARE = 0.02  # the band around each hole given the photos' colour, x image width: twice inpaint's growth


def photo_colours(points: np.ndarray, cameras: list[Camera], photos: list[Array], depths: list[Array],
                  occluders: list[Array], rel_tol: float, near: float | None,
                  device: torch.device | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) uint8: each of `points` (N, 3) as the photos that see it show it (the median per channel), and (N,)
    bool: whether any does (where none does, the colour is 0). Seeing is engine.io.visibility.visible_from's test
    (depths: the views' removed surfaces; occluders: what hides the surface in each photo)."""
    device = device or pick_device("auto")
    points = as_tensor(points, device, torch.float64)
    samples = torch.full((len(cameras), len(points), 3), float("nan"), dtype=torch.float32, device=device)
    for k, (camera, photo, depth, occluder) in enumerate(zip(cameras, photos, depths, occluders, strict=True)):
        visible, u, v = visible_from(camera, as_tensor(depth, device), points, rel_tol, as_tensor(occluder, device),
                                     near)
        colour = sample_pixels(as_tensor(photo, device), u, v)[0].float()
        samples[k] = torch.where(visible[:, None], colour, samples[k])
    seen = ~torch.isnan(samples[..., 0]).all(dim=0)
    median = torch.nan_to_num(torch.nanmedian(samples, dim=0).values, nan=0.0)
    return median.round().clamp(0, 255).to(torch.uint8).cpu().numpy(), seen.cpu().numpy()


def photo_view(camera: Camera, zone: np.ndarray, depth: np.ndarray, cameras: list[Camera], photos: list[Array],
               depths: list[Array], occluders: list[Array], rel_tol: float, near: float | None,
               device: torch.device | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(H, W, 3) uint8 and (H, W) bool: the photos' colour of each `zone` pixel's surface point (at `depth` along
    its ray) and where some photo saw it (photo_colours)."""
    image, seen = np.zeros((*zone.shape, 3), np.uint8), np.zeros_like(zone)
    ys, xs = np.nonzero(zone & np.isfinite(depth) & (depth > 0))
    if len(ys):
        u, v = pixel_grid(camera)
        points = backproject(camera, u[ys, xs], v[ys, xs], depth[ys, xs])
        image[ys, xs], seen[ys, xs] = photo_colours(points, cameras, photos, depths, occluders, rel_tol, near, device)
    return image, seen


def invented(hole: np.ndarray, seen: np.ndarray | None) -> np.ndarray:
    """The pixels of `hole` (as inpainted, grown) that an inpainter fills: those no photo saw (`seen`: holes'
    photo mask, None where the holes folder has none: all of them)."""
    return hole if seen is None else hole & ~seen
