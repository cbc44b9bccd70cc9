"""Which 3D points some view sees: the test behind ground-truth holes and (later) 3DGIC hole masks.

A view sees a world point when the point projects inside its frame with z > 0 and is not behind the
surface that view's depth map records there (within a relative tolerance).

The tests of many points against many views (seen_by_any, inside_visual_hull, and engine.edit.border's photo
test) run in torch, in float64, on `device` (default: the GPU when there is one): a capture's hole pixels are
tested against every training view, and in numpy that took 186 of the skull capture's 933 s (66 photos at 1424 px,
079d852) and grows with the square of the photos' count. The arithmetic is engine.formats.cameras' project and
sample_nearest (numpy only: Blender's Python shares that module), so the answers are the same.
"""

from __future__ import annotations

import cv2
import numpy as np
import torch

from engine.base.device import pick_device
from engine.formats.cameras import Camera, backproject, pixel_grid, project, sample_nearest

Array = np.ndarray | torch.Tensor  # an image or depth map on either side (tensors stay where they are)

DEFAULT_REL_TOL = 0.01  # 1% of depth: for rendered (trained) depth, blurred past Cycles' jitter; exact_tolerance's cap


def exact_tolerance(cameras: list[Camera]) -> float:
    """The depth tolerance for exact (rendered, not trained) depth maps: 2/focal of depth, at most 1%.

    Cycles' depth is one sample anywhere in the pixel, so on a slanted surface it jitters by up to half a
    pixel of depth slope: 1.9/focal of depth where a ray meets the surface at 15 degrees (a point met
    more obliquely by one view is seen by others), so the tolerance must follow the pixel. A
    fixed 1% is 8 mm at 0.8 m, and at 640 px it called points 2-7 mm behind the tabletop's toy seen
    (its exact holes a third too small; docs/BENCHMARKS.md, "Hole masks"). Small images keep 1%.
    """
    focal = min(min(c.fx, c.fy) for c in cameras)
    return min(DEFAULT_REL_TOL, 2.0 / focal)


def farthest_nearby(depth: np.ndarray, pixels: int = 1, exclude: np.ndarray | None = None) -> np.ndarray:
    """`depth` (H, W) with each pixel's farthest depth within `pixels` (inf is farthest), for rendered depth.

    A render blends an object's edge into the pixels beside it, nearer than the surface they show, so a
    point seen just past an edge (through the gap under a toy, beside a plush's overhang) fails the depth
    test. Exact depth has no such blur: the scene generator's holes/ test it as it is. `exclude` (bool, H, W):
    pixels that lend their depth to none of their neighbours and keep their own (the removed object's region,
    where a render of the scene without it looks through to whatever lay behind)."""
    kernel = np.ones((2 * pixels + 1, 2 * pixels + 1), np.uint8)
    if exclude is None:
        return cv2.dilate(depth.astype(np.float32), kernel)
    farthest = cv2.dilate(np.where(exclude, 0, depth).astype(np.float32), kernel)
    return np.where(exclude, depth, farthest).astype(np.float32)


def seen_by_any(points: np.ndarray, cameras: list[Camera], depths: list[Array],
                rel_tol: float = DEFAULT_REL_TOL, occluders: list[Array] | None = None,
                near: float | None = None, device: torch.device | None = None) -> np.ndarray:
    """(N,) bool: whether any of `cameras` (with z-depth maps `depths`) sees each of `points` (N, 3).

    `occluders` (one bool mask per camera, optional): pixels showing an occluding object, which see
    nothing behind it whatever the depths say. Rendered depth is blurred at silhouettes, and where an
    object touches its support the two depths differ by less than any tolerance; the masks decide there.

    `near` (optional, for rendered depth): the depth up to which `rel_tol` holds; beyond it the tolerance
    grows in proportion to depth, since a depth triangulated from views is uncertain in proportion to
    depth squared (a backdrop five times farther than the object is known to 5 rel_tol; at 1% it came out
    'unseen' behind a livingroom's plush).
    """
    device = device or pick_device("auto")
    points = as_tensor(points, device, torch.float64)
    seen = torch.zeros(len(points), dtype=torch.bool, device=device)
    for k, (camera, depth) in enumerate(zip(cameras, depths, strict=True)):
        todo = torch.nonzero(~seen)[:, 0]
        if not len(todo):
            break
        visible, _, _ = visible_from(camera, as_tensor(depth, device), points[todo], rel_tol,
                                     None if occluders is None else as_tensor(occluders[k], device), near)
        seen[todo[visible]] = True
    return seen.cpu().numpy()


def visible_from(camera: Camera, depth: torch.Tensor, points: torch.Tensor, rel_tol: float = DEFAULT_REL_TOL,
                 occluder: torch.Tensor | None = None, near: float | None = None
                 ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """(N,) bool: whether one camera (z-depth `depth`, `occluder` mask) sees each of `points` (N, 3, float64), as
    seen_by_any tests it; and the points' pixel coordinates u, v there. Tensors on one device."""
    u, v, z = project_points(camera, points)
    surface, inside = sample_pixels(depth, u, v)
    tol = rel_tol if near is None else rel_tol * torch.clamp_min(surface / near, 1.0)
    visible = inside & (z > 0) & (z <= surface * (1 + tol))
    if occluder is not None:
        visible &= ~sample_pixels(occluder, u, v)[0]
    return visible, u, v


def as_tensor(array: Array, device: torch.device, dtype: torch.dtype | None = None) -> torch.Tensor:
    """`array` as a tensor on `device` (no copy where it is one there already)."""
    return torch.as_tensor(np.ascontiguousarray(array) if isinstance(array, np.ndarray) else array,
                           device=device, dtype=dtype)


def project_points(camera: Camera, points: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """engine.formats.cameras.project in torch: world points (N, 3, float64) to pixel u, v and camera z."""
    rotation = torch.as_tensor(camera.R, dtype=torch.float64, device=points.device)
    cam = points @ rotation.T + torch.as_tensor(camera.t, dtype=torch.float64, device=points.device)
    z = cam[:, 2]
    return camera.fx * cam[:, 0] / z + camera.cx, camera.fy * cam[:, 1] / z + camera.cy, z


def sample_pixels(image: torch.Tensor, u: torch.Tensor, v: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """engine.formats.cameras.sample_nearest in torch: `image` (H, W[, C]) at the pixels holding (u, v), and
    which lie inside (outside ones and non-finite coordinates read pixel (0, 0))."""
    h, w = image.shape[:2]
    col, row = _pixel_index(u), _pixel_index(v)
    inside = (col >= 0) & (col < w) & (row >= 0) & (row < h)
    return image[torch.where(inside, row, 0), torch.where(inside, col, 0)], inside


def _pixel_index(x: torch.Tensor) -> torch.Tensor:
    """floor(x) as int64; non-finite or huge values become -1 (engine.formats.cameras._pixel_index)."""
    return torch.floor(torch.nan_to_num(x, nan=-1.0, posinf=-1.0, neginf=-1.0).clamp(-1.0, 1e9)).long()


def inside_visual_hull(means: np.ndarray, cameras: list[Camera], masks: list[Array], min_views: int = 3,
                       share: float = 1.0, device: torch.device | None = None) -> np.ndarray:
    """(N,) bool: in frame in at least `min_views` views and inside the mask in `share` of the views that
    frame it (all of them by default)."""
    device = device or pick_device("auto")
    means = as_tensor(means, device, torch.float64)
    framed = torch.zeros(len(means), dtype=torch.int32, device=device)
    inside = torch.zeros(len(means), dtype=torch.int32, device=device)
    for camera, mask in zip(cameras, masks, strict=True):
        u, v, z = project_points(camera, means)
        hit, in_frame = sample_pixels(as_tensor(mask, device), u, v)
        in_frame &= z > 0
        framed += in_frame
        inside += in_frame & hit
    return ((framed >= min_views) & (inside >= share * framed)).cpu().numpy()


def unseen_mask(camera: Camera, region: np.ndarray, background_depth: np.ndarray, cameras: list[Camera],
                depths: list[Array], rel_tol: float = DEFAULT_REL_TOL,
                occluders: list[Array] | None = None, near: float | None = None,
                device: torch.device | None = None) -> np.ndarray:
    """(H, W) bool: pixels of `region` whose background surface no view in `cameras` sees.

    The background surface of pixel p is the point at `background_depth[p]` along p's ray. Pixels
    with no finite background (open sky) count as seen: nothing is missing there.
    """
    u, v = pixel_grid(camera)
    candidates = region & np.isfinite(background_depth) & (background_depth > 0)
    points = backproject(camera, u[candidates], v[candidates], background_depth[candidates])
    hole = np.zeros_like(region, dtype=bool)
    hole[candidates] = ~seen_by_any(points, cameras, depths, rel_tol, occluders, near, device)
    return hole


SKY_DISTANCE = 1e4  # a sky pixel's point along its ray: far enough that only its direction counts


def unseen_view_pixels(camera: Camera, depth: np.ndarray, cameras: list[Camera], depths: list[np.ndarray],
                       rel_tol: float = DEFAULT_REL_TOL) -> np.ndarray:
    """(H, W) bool: the pixels of a view (z-depth `depth`) that none of `cameras` saw, the object included.

    Why: a test view may show what no training view had in frame (sky past their edges, a surface they never
    faced), which no training can know; the statue's worst test view held 65% of its error in 0.5% of such
    pixels (docs/BENCHMARKS.md, "Training"). A surface point is seen as in seen_by_any; sky (infinite depth) is a
    direction, seen where a view has that direction in frame and shows sky there too."""
    u, v = pixel_grid(camera)
    sky = ~np.isfinite(depth)
    unseen = np.zeros(depth.shape, bool)
    surface = backproject(camera, u[~sky], v[~sky], depth[~sky])
    unseen[~sky] = ~seen_by_any(surface, cameras, depths, rel_tol)
    ahead = backproject(camera, u[sky], v[sky], np.full(int(sky.sum()), SKY_DISTANCE)) - camera.center
    sky_seen = np.zeros(len(ahead), bool)
    for other, other_depth in zip(cameras, depths, strict=True):
        pu, pv, z = project(other, other.center + ahead)
        shown, inside = sample_nearest(other_depth, pu, pv)
        sky_seen |= inside & (z > 0) & ~np.isfinite(shown)
    unseen[sky] = ~sky_seen
    return unseen
