"""2D fills on exact data, the inpainters alone: each scored view's true hole (holes/) blanked in the truth (gt/)
and filled by each inpainter, m-PSNR (and m-ST-LPIPS where its weights are set up) against the truth in the hole,
and seconds per megapixel. What the 3D pipeline adds (a removal's leftovers at the hole's border, the masks' growth,
depth, training) is not in it: a screen for which 2D fills are worth a cell in the held-out table, the ceiling
the 3D pipeline's fill could reach, and the PatchMatch libraries from the registry beside ours.

With `--plane`, each of ours also fills through the support plane's texture (engine.complete.plane_texture, Ref's
`plane_texture` option) on exact data: the plane fitted to the truth's depth around the training views' true holes,
the texture gathered from the training views' truth outside them, inpainted once and carried into each scored view
(its pixels off the plane keep the view's own fill).

With `--grow PX` the region blanked and filled is the true hole grown by PX (as `inpaint` grows the masks, 4% of
the width by default), still scored in the true hole: what the growth alone costs each fill.

    PYTHONPATH=. python benchmarks/fill_2d.py SCENE... [--plane] [--grow PX] [--only NAME...] [--json OUT]

The test views are scored (those the held-out table scores). The PatchMatch libraries are not the engine's
requirements: `pip install patchmatch-cython pypatchmatch` where this runs (a missing one is skipped and named).
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from engine.capture.scene import Scene, load_scene
from engine.inpaint.registry import create
from engine.io.masks import dilate
from engine.metrics.image_metrics import masked_psnr

OURS = ("telea", "navier-stokes", "fsr", "exemplar", "coherence", "coherence-smooth")
MIN_HOLE_PX = 20  # views with a smaller true hole are not scored
RING_PX = 6  # the plane is fitted to the truth's depth this far around the training views' true holes
PLANE_TOL = 0.03  # share of the depth a ring point may lie off the plane (engine.edit.support_plane)


def inpainters(only: list[str] | None = None) -> tuple[dict[str, object], dict[str, Callable], dict[str, str]]:
    """Our inpainters (name -> Inpainter), name -> fill(rgb, hole) for ours and the registry's PatchMatch
    libraries (those of `only` where given), and those that could not load."""
    ours, fills, missing = {}, {}, {}
    for name in OURS:
        if only and name not in only:
            continue
        try:
            ours[name] = create(name)
        except Exception as exc:  # an inpainter whose requirement is absent here (fsr without contrib)
            missing[name] = str(exc)
            continue
        fills[name] = lambda im, m, inp=ours[name]: inp.inpaint(im, m, "rgb")
    if only and not {"patchmatch-cython", "pypatchmatch"} & set(only):
        return ours, fills, missing
    try:
        import patchmatch_cython

        fills["patchmatch-cython"] = lambda im, m: patchmatch_cython.inpaint_pyramid(im, m.astype(np.uint8))
    except ImportError as exc:
        missing["patchmatch-cython"] = str(exc)
    try:
        from patchmatch import patch_match

        patch_match.set_random_seed(0)
        fills["pypatchmatch"] = lambda im, m: patch_match.inpaint(im, m.astype(np.uint8) * 255, patch_size=3)
    except ImportError as exc:
        missing["pypatchmatch"] = str(exc)
    return ours, fills, missing


class PlaneTexture:
    """The support plane's texture on exact data (see the module docstring), ready to be filled by an inpainter
    and carried into a view."""

    def __init__(self, scene: Scene, scored: list[int]) -> None:
        from engine.complete.plane_texture import gather, texture_grid
        from engine.edit.support_plane import Footprint, plane_along_rays, support_plane

        self.scene = scene
        train = [i for i in scene.train if i in scene.holes and scene.holes[i].any()]
        cameras = [scene.cameras[i] for i in train]
        self.plane = support_plane(cameras, [dilate(scene.holes[i], RING_PX) & ~scene.holes[i] for i in train],
                                   [scene.gt_depths[i] for i in train], PLANE_TOL)
        if self.plane is None:
            return
        points = []
        for i in train:
            ys, xs = np.nonzero(scene.holes[i])
            unit, z = plane_along_rays(scene.cameras[i], ys, xs, self.plane)
            ahead = np.isfinite(z) & (z > 0)
            points.append(scene.cameras[i].center + unit[ahead] * z[ahead, None])
        footprint = Footprint.of(np.concatenate(points), self.plane[0]) if points else None
        if footprint is None:  # under 20 hole pixels meet the plane: no texture to speak of
            self.plane = None
            return
        self.grid = texture_grid(self.plane, footprint, cameras)
        self.texture, self.seen, needed = gather(self.grid, cameras, [scene.gt_images[i] for i in train],
                                                 [scene.holes[i] for i in train], [scene.gt_depths[i] for i in train])
        _, _, scored_needs = gather(self.grid, [scene.cameras[i] for i in scored],
                                    [scene.gt_images[i] for i in scored], [scene.holes[i] for i in scored],
                                    [scene.gt_depths[i] for i in scored])
        self.needed = (needed | scored_needs) & ~self.seen

    def fill(self, inpainter) -> np.ndarray:
        from engine.complete.plane_texture import fill_texture

        return fill_texture(self.texture, self.seen, self.needed, inpainter)

    def carry(self, filled: np.ndarray, view: int, image: np.ndarray) -> tuple[np.ndarray, int]:
        """`image` (the view's own fill) with its true hole's on-plane pixels read from the filled texture, and
        how many were."""
        from engine.complete.plane_texture import apply_texture

        scene = self.scene
        out, placed = apply_texture(self.grid, filled, self.seen | self.needed, scene.cameras[view],
                                    scene.holes[view], scene.gt_depths[view], image)
        return out, int(placed.sum())


def scorer():
    """The m-ST-LPIPS network where the set-up's weights are, else None (m-PSNR alone)."""
    from engine.metrics.scores import ScoreConfig, Scorer

    loaded = Scorer(ScoreConfig())
    return loaded if loaded.st_lpips is not None else None


def perceptual(network, image: np.ndarray, truth: np.ndarray, hole: np.ndarray) -> float | None:
    if network is None:
        return None
    return network.score([image], [truth], [hole]).values["m_st_lpips"]


def score(scene_dir: Path, ours: dict, fills: dict[str, Callable], plane: bool, network,
          grow: int = 0) -> dict[str, list[dict]]:
    """Per fill (and with `plane`, per `plane-` fill of ours), per scored view: m-PSNR, m-ST-LPIPS, seconds per
    megapixel (of the view's own fill), and for the plane fills the share of the hole read from the texture; the
    true hole grown by `grow` px is what is blanked and filled."""
    scene = load_scene(scene_dir, depth=plane)
    scored = [i for i in scene.test if i in scene.holes and scene.holes[i].sum() >= MIN_HOLE_PX]
    texture = PlaneTexture(scene, scored) if plane else None
    filled = {name: texture.fill(ours[name]) for name in ours} if texture and texture.plane is not None else {}
    out: dict[str, list[dict]] = {name: [] for name in [*fills, *(f"plane-{n}" for n in filled)]}
    for i in scored:
        truth, hole = scene.gt_images[i], scene.holes[i]
        filled_region = dilate(hole, grow) if grow else hole
        blank = truth.copy()
        blank[filled_region] = 0
        for name, fill in fills.items():
            start = time.perf_counter()
            image = fill(blank, filled_region)
            seconds = time.perf_counter() - start
            out[name].append({"m_psnr": masked_psnr(image, truth, hole), "s_per_mp": seconds / (hole.size / 1e6),
                              "m_st_lpips": perceptual(network, image, truth, hole)})
            if name in filled:
                carried, placed = texture.carry(filled[name], i, image)
                out[f"plane-{name}"].append({"m_psnr": masked_psnr(carried, truth, hole), "placed": placed / hole.sum(),
                                             "m_st_lpips": perceptual(network, carried, truth, hole)})
    return out


def summary(views: list[dict]) -> dict:
    keys = [k for k in views[0] if views[0][k] is not None]
    return {**{k: round(float(np.mean([v[k] for v in views])), 4) for k in keys}, "views": len(views)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="+", type=Path)
    parser.add_argument("--plane", action="store_true", help="also fill ours through the support plane's texture")
    parser.add_argument("--grow", type=int, default=0, help="px the blanked and filled region grows past the hole")
    parser.add_argument("--only", nargs="+", help="these fills alone (names as in the output)")
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    ours, fills, missing = inpainters(args.only)
    network = scorer()
    table = {}
    for scene in args.scenes:
        scored = score(scene, ours, fills, args.plane, network, args.grow)
        table[scene.name] = {name: summary(v) for name, v in scored.items() if v}
        print(scene.name, {k: (v["m_psnr"], v.get("m_st_lpips")) for k, v in table[scene.name].items()}, flush=True)
    names = sorted({n for s in table.values() for n in s}, key=lambda n: (n.startswith("plane-"), n))
    means = {n: {k: round(float(np.mean([table[s][n][k] for s in table])), 4) for k in ("m_psnr", "m_st_lpips")
                 if all(k in table[s].get(n, {}) for s in table)} for n in names}
    print("means", means, "missing", missing or "none")
    if args.json:
        args.json.write_text(json.dumps({"scenes": table, "means": means, "missing": missing, "grow_px": args.grow,
                                         "perceptual": "m_st_lpips" if network else "none (no ST-LPIPS weights)"},
                                        indent=1))


if __name__ == "__main__":
    main()
