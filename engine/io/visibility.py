"""Which 3D points some view sees: the test behind ground-truth holes and (later) 3DGIC hole masks.

A view sees a world point when the point projects inside its frame with z > 0 and is not behind the
surface that view's depth map records there (within a relative tolerance).
"""

from __future__ import annotations

import cv2
import numpy as np
import torch

from engine.formats.cameras import Camera, backproject, pixel_grid

CPU_GROUP = 8  # views tested together on the CPU (ViewStack.groups)
DEFAULT_REL_TOL = 0.01  # 1% of depth: for rendered (trained) depth, blurred past Cycles' jitter; exact_tolerance's cap


def exact_tolerance(cameras: list[Camera]) -> float:
    """The depth tolerance for exact (rendered, not trained) depth maps: 2/focal of depth, at most 1%.

    Cycles' depth is one sample anywhere in the pixel, so on a slanted surface it jitters by up to half a
    pixel of depth slope: 1.9/focal of depth where a ray meets the surface at 15 degrees (a point met
    more obliquely by one view is seen by others), so the tolerance must follow the pixel. A
    fixed 1% is 8 mm at 0.8 m, and at 640 px it called points 2-7 mm behind the tabletop's toy seen
    (its exact holes a third too small; docs/BENCHMARKS.md, "Eighth trainings"). Small images keep 1%.
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


class ViewStack:
    """Cameras, each with maps of one size (z-depth, masks), stacked as tensors on one device.

    Why: a stage tests many points against every view (holes: each of 100 views' object pixels against 90
    training views; the generator's exact holes alike). One batched projection and one gather per map do what a
    Python loop of numpy calls per view did, on the GPU where there is one, and the maps go to the device once
    for every point the stage tests. Views of other sizes are padded to the largest; each keeps its own frame."""

    def __init__(self, cameras: list[Camera], maps: dict[str, list[np.ndarray]], device: torch.device | str = "cpu"
                 ) -> None:
        first = next(iter(maps.values()))
        shapes = [m.shape[:2] for m in first]
        for name, layers in maps.items():
            if len(layers) != len(cameras) or [m.shape[:2] for m in layers] != shapes:
                raise ValueError(f"map {name!r}: one per camera, each the size of that camera's other maps")
        self.device = torch.device(device)
        f64 = {"dtype": torch.float64, "device": self.device}
        self.rotations = torch.as_tensor(np.stack([c.R for c in cameras]), **f64)
        self.translations = torch.as_tensor(np.stack([c.t for c in cameras]), **f64)
        self.intrinsics = torch.as_tensor(np.array([[c.fx, c.fy, c.cx, c.cy] for c in cameras]), **f64)
        self.sizes = torch.as_tensor(np.array([[w, h] for h, w in shapes]), device=self.device)
        self.shape = (max(h for h, _ in shapes), max(w for _, w in shapes))
        self.maps = {name: self._stack(layers) for name, layers in maps.items()}

    def __len__(self) -> int:
        return len(self.rotations)

    def _stack(self, layers: list[np.ndarray]) -> torch.Tensor:
        stacked = np.zeros((len(layers), *self.shape), layers[0].dtype)
        for k, layer in enumerate(layers):
            stacked[k, :layer.shape[0], :layer.shape[1]] = layer
        return torch.from_numpy(stacked).to(self.device).reshape(-1)

    def groups(self) -> list[slice]:
        """The views in groups tested together: all at once on a GPU (a few kernels each); on the CPU a few
        at a time, so that the points one group sees are not tested against the next (numpy's loop over views
        did that one view at a time, and testing every point against every view was 4.5x slower than it)."""
        size = len(self) if self.device.type == "cuda" else CPU_GROUP
        return [slice(k, k + size) for k in range(0, len(self), size)]

    def chunks(self, points: np.ndarray) -> list[torch.Tensor]:
        """`points` (N, 3) on the device in pieces small enough that one group's projection of a piece stays
        small: on the CPU, in cache (whole-array temporaries of every view at once were 2.5x slower)."""
        budget = 1 << 22 if self.device.type == "cuda" else 1 << 16
        size = max(1, budget // (self.groups()[0].stop - self.groups()[0].start))
        tensor = torch.as_tensor(np.asarray(points, dtype=np.float64).reshape(-1, 3), device=self.device)
        return list(torch.split(tensor, size)) if len(tensor) else [tensor]

    def locate(self, points: torch.Tensor, views: slice = slice(None), directions: bool = False
               ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Each of the `views`' pixel of each of `points` (N, 3): (V, N) index into the stacked maps, whether it
        lies inside that view's frame, and its camera z. `directions`: the points are directions, each placed
        along it from every camera's own centre (sky). As engine.formats.cameras.project and sample_nearest."""
        cam = torch.matmul(points[None], self.rotations[views].transpose(1, 2))
        if not directions:
            cam = cam + self.translations[views, None]
        z = cam[..., 2]
        fx, fy, cx, cy = (self.intrinsics[views, k, None] for k in range(4))
        col, row = _pixel_index(fx * cam[..., 0] / z + cx), _pixel_index(fy * cam[..., 1] / z + cy)
        sizes = self.sizes[views]
        inside = (col >= 0) & (col < sizes[:, :1]) & (row >= 0) & (row < sizes[:, 1:])
        height, width = self.shape
        ids = torch.arange(len(self), device=self.device)[views, None]
        index = (ids * height + torch.where(inside, row, 0)) * width + torch.where(inside, col, 0)
        return index, inside, z

    def visible(self, points: np.ndarray, rel_tol: float = DEFAULT_REL_TOL, near: float | None = None,
                occluder: str | None = None) -> np.ndarray:
        """(C, N) bool: whether each view sees each of `points` (N, 3) by its "depth" map, as seen_by_any."""
        return torch.cat([torch.cat([self._visible(chunk, views, rel_tol, near, occluder) for views in self.groups()])
                          for chunk in self.chunks(points)], 1).cpu().numpy()

    def _visible(self, points: torch.Tensor, views: slice, rel_tol: float, near: float | None,
                 occluder: str | None) -> torch.Tensor:
        index, inside, z = self.locate(points, views)
        surface = self.maps["depth"][index]
        tol = rel_tol if near is None else rel_tol * torch.clamp(surface / near, min=1.0)
        visible = inside & (z > 0) & (z <= surface * (1 + tol))
        return visible & ~self.maps[occluder][index] if occluder is not None else visible


def _pixel_index(x: torch.Tensor) -> torch.Tensor:
    """floor(x) as int64; non-finite or huge values become -1 (engine.formats.cameras._pixel_index)."""
    return torch.floor(torch.nan_to_num(x, nan=-1.0, posinf=-1.0, neginf=-1.0).clamp(-1.0, 1e9)).long()


def seen_by_any(points: np.ndarray, views: ViewStack, rel_tol: float = DEFAULT_REL_TOL, near: float | None = None,
                occluder: str | None = None) -> np.ndarray:
    """(N,) bool: whether any of the `views` (their "depth" maps: z-depth) sees each of `points` (N, 3).

    `occluder` (optional): the name of a bool map per view of pixels showing an occluding object, which see
    nothing behind it whatever the depths say. Rendered depth is blurred at silhouettes, and where an
    object touches its support the two depths differ by less than any tolerance; the masks decide there.

    `near` (optional, for rendered depth): the depth up to which `rel_tol` holds; beyond it the tolerance
    grows in proportion to depth, since a depth triangulated from views is uncertain in proportion to
    depth squared (a backdrop five times farther than the object is known to 5 rel_tol; at 1% it came out
    'unseen' behind a livingroom's plush).
    """
    out = []
    for chunk in views.chunks(points):
        seen = torch.zeros(len(chunk), dtype=torch.bool, device=views.device)
        for group in views.groups():
            todo = torch.nonzero(~seen)[:, 0]
            if len(todo) == 0:
                break
            seen[todo] = views._visible(chunk[todo], group, rel_tol, near, occluder).any(0)
        out.append(seen)
    return torch.cat(out).cpu().numpy()


def inside_visual_hull(means: np.ndarray, views: ViewStack, mask: str = "mask", min_views: int = 3,
                       share: float = 1.0) -> np.ndarray:
    """(N,) bool: in frame in at least `min_views` of the `views` and inside their `mask` map (bool) in
    `share` of the views that frame it (all of them by default)."""
    out = []
    for chunk in views.chunks(means):
        count = hits = 0
        for group in views.groups():
            index, inside, z = views.locate(chunk, group)
            framed = inside & (z > 0)
            count, hits = count + framed.sum(0), hits + (framed & views.maps[mask][index]).sum(0)
        out.append((count >= min_views) & (hits >= share * count))
    return torch.cat(out).cpu().numpy()


def unseen_mask(camera: Camera, region: np.ndarray, background_depth: np.ndarray, views: ViewStack,
                rel_tol: float = DEFAULT_REL_TOL, near: float | None = None, occluder: str | None = None
                ) -> np.ndarray:
    """(H, W) bool: pixels of `region` whose background surface none of the `views` sees (seen_by_any).

    The background surface of pixel p is the point at `background_depth[p]` along p's ray. Pixels
    with no finite background (open sky) count as seen: nothing is missing there.
    """
    u, v = pixel_grid(camera)
    candidates = region & np.isfinite(background_depth) & (background_depth > 0)
    points = backproject(camera, u[candidates], v[candidates], background_depth[candidates])
    hole = np.zeros_like(region, dtype=bool)
    hole[candidates] = ~seen_by_any(points, views, rel_tol, near, occluder)
    return hole


SKY_DISTANCE = 1e4  # a sky pixel's point along its ray: far enough that only its direction counts


def unseen_view_pixels(camera: Camera, depth: np.ndarray, views: ViewStack, rel_tol: float = DEFAULT_REL_TOL
                       ) -> np.ndarray:
    """(H, W) bool: the pixels of a view (z-depth `depth`) that none of the `views` (their "depth") saw, the
    object included.

    Why: a test view may show what no training view had in frame (sky past their edges, a surface they never
    faced), which no training can know; the statue's worst test view held 65% of its error in 0.5% of such
    pixels (docs/BENCHMARKS.md, "Run 7"). A surface point is seen as in seen_by_any; sky (infinite depth) is a
    direction, seen where a view has that direction in frame and shows sky there too."""
    u, v = pixel_grid(camera)
    sky = ~np.isfinite(depth)
    unseen = np.zeros(depth.shape, bool)
    surface = backproject(camera, u[~sky], v[~sky], depth[~sky])
    unseen[~sky] = ~seen_by_any(surface, views, rel_tol)
    ahead = backproject(camera, u[sky], v[sky], np.full(int(sky.sum()), SKY_DISTANCE)) - camera.center
    sky_seen = []
    for chunk in views.chunks(ahead):
        index, inside, z = views.locate(chunk, directions=True)
        sky_seen.append((inside & (z > 0) & ~torch.isfinite(views.maps["depth"][index])).any(0))
    unseen[sky] = ~torch.cat(sky_seen).cpu().numpy()
    return unseen
