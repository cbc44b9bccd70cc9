"""The plane an object rests on, and rays that the removed scene lets through it.

Where an object touched its support, no view saw the support, so 3DGS never built that patch of surface.
After removal the render there looks *through* the missing patch at what lies below (the table's
underside, the floor), which side views did see: measured on the livingroom scene, the removed depth in
the true hole is 4-13% deeper than the real table top, and a depth-warping test calls those pixels seen
(docs/BENCHMARKS.md). Fitting the support plane to the surfaces around the object's base in the training
views and stopping each ray of the object's region at that plane restores the surface that should be
there; a warp from the plane then finds it hidden by the object in every view.

Objects on a plane (a table, a slab, mats) are the scenes this toolkit generates and the paper uses, and objects
mounted on a wall (`object_support` takes the wall where the object hangs on it); with no clear plane around the
object, nothing changes. The level planes (floor, table top) that the same
cameras' up vector picks out also serve `segment --auto` (engine.segment.proposals), which splits what rests
on them into objects.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from engine.edit.plane_grid import PlaneFrame
from engine.formats.cameras import Camera, backproject, pixel_grid
from engine.formats.checks import read_json
from engine.formats.layout import RemovedLayout
from engine.geometry.planes import fit_plane, level_normal, support_planes, tilted_planes
from engine.io.gaussians import Gaussians
from engine.io.masks import dilate

RING_PX = (3, 9)  # the band around the object's region whose surfaces may be its support (its edge is blurred)
HORIZONTAL_SHARE = 0.1  # a level plane needs fewer: cameras' up rules out walls and slanted clutter
SURROUND_SECTORS, SURROUND_NEED = 8, 5  # a support's points near the object lie in 5 of 8 sectors around it
SPREAD = 0.25  # ... and spread at least this share of its radius across the plane's narrowest way (not a line)
IN_FRONT = 0.85  # share of the object's core in front of a wall (a plane through the object halves it)
WALL_GAP = 0.15  # a wall supports an object whose nearest part stands off it by at most this share of its size


def ring_points(camera: Camera, region: np.ndarray, depth: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Surface points (N, 3) in a band around `region`, lifted with `depth`, and their depths (N,)."""
    band = dilate(region, RING_PX[1]) & ~dilate(region, RING_PX[0]) & np.isfinite(depth)
    u, v = pixel_grid(camera)
    return backproject(camera, u[band], v[band], depth[band]), depth[band]


def support_plane(cameras: list[Camera], regions: list[np.ndarray], depths: list[np.ndarray], rel_tol: float,
                  up: np.ndarray | None = None) -> tuple[np.ndarray, float] | None:
    """The plane through most surfaces around the object's regions in these views (tolerance: rel_tol of
    their median depth), or None. Where no plane holds MIN_INLIER_SHARE of them (a capture's rendered
    depth is noisier than a generated scene's: 17% agreed on one around an SfM livingroom's plush, 42% on
    exact depth) and the cameras tell `up`, the level plane holding the most of them, if it holds
    HORIZONTAL_SHARE."""
    rings = [ring_points(c, r, d) for c, r, d in zip(cameras, regions, depths, strict=True) if r.any()]
    if not rings:
        return None
    points = np.concatenate([p for p, _ in rings])
    tol = rel_tol * float(np.median(np.concatenate([d for _, d in rings])))
    plane = fit_plane(points, tol)
    if plane is None and up is not None:
        level = support_planes(points, up, tol, HORIZONTAL_SHARE, most=1)
        plane = level[0] if level else None
    return plane


def removal_plane(removed: RemovedLayout) -> tuple[np.ndarray, float] | None:
    """The support plane `remove` fitted to the remaining Gaussians (object_support) and wrote to its
    report, if it found one: the Gaussians' centres put it within mm, rendered depth within cm."""
    plane = read_json(removed.report).get("support_plane") if removed.report.is_file() else None
    return (np.asarray(plane[:3], dtype=np.float64), float(plane[3])) if plane else None


def plane_along_rays(camera: Camera, ys: np.ndarray, xs: np.ndarray, plane: tuple[np.ndarray, float]
                     ) -> tuple[np.ndarray, np.ndarray]:
    """For pixels (ys, xs): each ray's step per unit of z-depth (N, 3) and the z-depth where it meets the
    plane (N,; inf or negative where it never does in front of the camera)."""
    normal, offset = plane
    u, v = pixel_grid(camera)
    unit = backproject(camera, u[ys, xs], v[ys, xs], np.ones(len(ys))) - camera.center
    with np.errstate(divide="ignore", invalid="ignore"):
        return unit, -(camera.center @ normal + offset) / (unit @ normal)


def axis_distance(points: np.ndarray, centre: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """(N,) each point's distance from the line through `centre` along the unit `axis`."""
    rel = points - centre
    return np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=1)


def stop_at_plane(camera: Camera, region: np.ndarray, depth: np.ndarray, plane: tuple[np.ndarray, float],
                  rel_tol: float) -> np.ndarray:
    """`depth` with each region pixel that lies beyond the plane (by more than rel_tol) moved onto it."""
    ys, xs = np.nonzero(region)
    _, z_plane = plane_along_rays(camera, ys, xs, plane)
    beyond = (z_plane > 0) & (depth[ys, xs] > z_plane * (1 + rel_tol))
    out = depth.copy()
    out[ys[beyond], xs[beyond]] = z_plane[beyond]
    return out


@dataclass(frozen=True)
class Footprint:
    """The object seen from straight above its support: a disc about its axis (`centre`, on the core's
    median) of `radius` (95% of the core's Gaussians lie within it), along `normal`."""

    centre: np.ndarray
    radius: float
    normal: np.ndarray

    @classmethod
    def of(cls, core: np.ndarray, normal: np.ndarray) -> Footprint | None:
        if len(core) < 20:
            return None
        centre = np.median(core, axis=0)
        return cls(centre, float(np.percentile(axis_distance(core, centre, normal), 95)), normal)

    def across(self, points: np.ndarray) -> np.ndarray:
        """(N,) each point's distance from the object's axis."""
        return axis_distance(points, self.centre, self.normal)

    def report(self) -> dict:
        return {"centre": np.round(self.centre, 6).tolist(), "radius": round(self.radius, 6),
                "normal": np.round(self.normal, 6).tolist()}


def removal_footprint(removed: RemovedLayout) -> Footprint | None:
    """The footprint `remove` wrote to its report, if any."""
    found = read_json(removed.report).get("footprint") if removed.report.is_file() else None
    if not found:
        return None
    return Footprint(np.asarray(found["centre"]), float(found["radius"]), np.asarray(found["normal"]))


def off_support(camera: Camera, region: np.ndarray, depth: np.ndarray, plane: tuple[np.ndarray, float],
                footprint: Footprint, tol: float) -> np.ndarray:
    """(H, W) bool: `region` pixels whose rendered surface (`depth`) lies off the plane by more than `tol`
    of the plane's depth, in front or beyond, where both that surface point and the ray's point on the
    plane lie within the object's footprint: the support under an overhang, seen only at grazing angles,
    left as a crater or a bulge of smeared texture."""
    ys, xs = np.nonzero(region & np.isfinite(depth))
    unit, z_plane = plane_along_rays(camera, ys, xs, plane)
    with np.errstate(divide="ignore", invalid="ignore"):
        off_plane = np.abs(depth[ys, xs] / z_plane - 1) > tol
    surface = camera.center + unit * depth[ys, xs][:, None]
    on_plane = camera.center + unit * z_plane[:, None]
    off = ((z_plane > 0) & off_plane
           & (footprint.across(surface) <= footprint.radius) & (footprint.across(on_plane) <= footprint.radius))
    out = np.zeros(region.shape, bool)
    out[ys[off], xs[off]] = True
    return out


def standing_on(camera: Camera, region: np.ndarray, depth: np.ndarray, plane: tuple[np.ndarray, float],
                tol: float) -> np.ndarray:
    """(H, W) bool: `region` pixels whose rendered surface (`depth`) lies in front of the plane, nearer the camera
    than where the ray meets it by more than `tol` of that depth: what stands on the support (or hangs on the wall),
    not the support. Rays that never meet the plane in front of the camera (the backdrop above a table's horizon)
    and surfaces beyond it (the floor past the table's edge) are not."""
    ys, xs = np.nonzero(region & np.isfinite(depth))
    _, z_plane = plane_along_rays(camera, ys, xs, plane)
    with np.errstate(invalid="ignore"):
        front = (z_plane > 0) & np.isfinite(z_plane) & (depth[ys, xs] < z_plane * (1 - tol))
    out = np.zeros(region.shape, bool)
    out[ys[front], xs[front]] = True
    return out


def object_core(removed: Gaussians, up: np.ndarray) -> np.ndarray:
    """(M, 3) the removed object's visible Gaussians (opacity > 0.1) without the strays the removal also
    took (floaters of its identity far away): those within 3x the median distance from its vertical axis."""
    points = removed["means"].numpy()[torch.sigmoid(removed["opacities"]).numpy() > 0.1]
    if len(points) < 20:
        return points[:0]
    centre = np.median(points, axis=0)
    across = axis_distance(points, centre, up)
    return points[across <= 3 * np.median(across)]


def object_support(means: np.ndarray, obj: np.ndarray, up: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The plane the object rests on or hangs from: the level one below it (a floor, a table top) or a wall
    behind it, whichever reaches around the object and lies nearer to it. A wall-mounted trophy's level
    candidate was a thin level face beside it (on a 300k-Gaussian run of the wall family, a plane through its
    plaque's lower edge, tilted 12 degrees): the hole masks stopped rays there and called the wall behind the
    plaque seen (IoU 0.22 against the true holes)."""
    level, wall = level_support(means, obj, up), wall_support(means, obj, up)
    if wall is None:
        return level
    if (level is None or not surrounds(means, obj, level) or not clear_of(obj, level)
            or abs(contact_gap(obj, wall)) < abs(contact_gap(obj, level))):
        return wall
    return level


def level_support(means: np.ndarray, obj: np.ndarray, up: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The highest level plane through the remaining Gaussians (`means`)
    around the object's core `obj` that lies below most of it (the removal may also have taken Gaussians
    under its base, inside its visual hull). Gaussians' centres lie on a trained surface to a few mm where
    its rendered depth does not (engine.render.surface_depth): fitted to rendered depth, a livingroom's table
    came out 2 degrees tilted and 0.5-4 cm low, and the hole masks' IoU 0.31 against 0.69 from this fit."""
    if len(obj) < 20:
        return None
    heights = obj @ up
    size = float(np.percentile(heights, 98) - np.percentile(heights, 2))
    centre = np.median(obj, axis=0)
    across = axis_distance(means, centre, up)
    radius = float(np.percentile(axis_distance(obj, centre, up), 95))
    ring = means[(across > radius) & (across < radius + size)]
    if len(ring) < 50:
        return None
    tol = 0.01 * max(size, 1e-6)
    normal = level_normal(means, up, tol)  # the scene's level, from all of it: a ring's own tilts through layers
    low = np.percentile(obj @ normal, 25)
    planes = [(n, d) for n, d in support_planes(ring, up, tol, share=0.05, most=4, normal=normal) if -d < low]
    if not planes:
        return None
    return max(planes, key=lambda plane: -plane[1])


def _toward(plane: tuple[np.ndarray, float], obj: np.ndarray) -> tuple[np.ndarray, float]:
    """The plane with its normal turned towards the object's median."""
    normal, offset = plane
    return (normal, offset) if np.median(obj @ normal) + offset >= 0 else (-normal, -offset)


def contact_gap(obj: np.ndarray, plane: tuple[np.ndarray, float]) -> float:
    """How far the object's nearest part (its 10th percentile) stands off the plane, on the object's side: past
    what the visual hull took behind a wall or under a table with it."""
    normal, offset = _toward(plane, obj)
    return float(np.percentile(obj @ normal + offset, 10))


def clear_of(obj: np.ndarray, plane: tuple[np.ndarray, float], share: float = 0.97) -> bool:
    """Whether the object lies wholly on one side of the plane (`share` of its core, within 2% of its size): a
    level plane through a plaque's lower part is no support, however near it is."""
    normal, offset = _toward(plane, obj)
    centre = np.median(obj, axis=0)
    tol = 0.02 * float(np.percentile(np.linalg.norm(obj - centre, axis=1), 95))
    return bool(((obj @ normal + offset) > -tol).mean() >= share)


def surrounds(means: np.ndarray, obj: np.ndarray, plane: tuple[np.ndarray, float]) -> bool:
    """Whether the plane's points near the object (within its size past its outline) lie on all sides of it:
    in SURROUND_NEED of SURROUND_SECTORS sectors about the object's axis along the plane's normal. A support
    reaches under or behind the object; a picture frame's edge or a shelf's face beside it does not."""
    normal, offset = _toward(plane, obj)
    centre = np.median(obj, axis=0)
    radius = float(np.percentile(axis_distance(obj, centre, normal), 95))
    size = max(radius, 1e-6)
    tol = 0.01 * 2 * size
    near = (np.abs(means @ normal + offset) < 2 * tol) & (axis_distance(means, centre, normal) < radius + size)
    if near.sum() < SURROUND_SECTORS:
        return False
    flat = PlaneFrame.of(normal, offset).flat(means[near] - centre)
    angle = np.arctan2(flat[:, 1], flat[:, 0])
    sectors = np.unique(((angle + np.pi) / (2 * np.pi) * SURROUND_SECTORS).astype(int) % SURROUND_SECTORS)
    spread = np.sqrt(np.linalg.eigvalsh(np.cov(flat.T))[0])  # across its narrowest way: a line has none
    return len(sectors) >= SURROUND_NEED and spread >= SPREAD * radius


def wall_support(means: np.ndarray, obj: np.ndarray, up: np.ndarray) -> tuple[np.ndarray, float] | None:
    """A plane that is not level (engine.geometry.planes.tilted_planes) among the remaining Gaussians within the
    object's size past its outline, that the object lies in front of (IN_FRONT of its core: the visual hull takes
    Gaussians inside the wall behind a plaque too), touches (its nearest part within WALL_GAP of its size) and
    that reaches around it (`surrounds`); the fullest such."""
    if len(obj) < 20:
        return None
    centre = np.median(obj, axis=0)
    radius = float(np.percentile(np.linalg.norm(obj - centre, axis=1), 95))
    distance = np.linalg.norm(means - centre, axis=1)
    shell = means[(distance > 0.5 * radius) & (distance < 2 * radius)]
    if len(shell) < 50:
        return None
    tol = 0.01 * 2 * radius
    for plane in tilted_planes(shell, up, tol, share=0.1, min_radius=0.5 * radius):
        normal, offset = _toward(plane, obj)
        side = obj @ normal + offset
        if ((side > -2 * tol).mean() >= IN_FRONT and contact_gap(obj, plane) <= WALL_GAP * 2 * radius
                and surrounds(means, obj, plane)):
            return normal, offset
    return None
