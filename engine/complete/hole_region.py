"""What a completion may change: the Gaussians that render into the hole and nowhere else.

Why: a completion that retrains the whole removed scene on the inpainted views relearns what removal had left
right, and blurs it (the statue capture's buildings were sharp after `remove` and soft after `complete`); the
inpainted views are only new inside the hole. So a completion trains the Gaussians of its hole alone:

- a Gaussian of the removed scene is *movable* when its centre falls inside the (dilated) hole of at least one
  view, and in every view where it lies in front of the camera, inside the image and not hidden behind the
  removed scene's surface there, inside that view's hole (hole_bound), and its visible ellipse lies in the holes
  too (changeable: a wide one centred in the hole renders past it). Everything else is the Trainer's `fixed` set:
  rendered every step, never changed (engine.train.trainer), so outside the holes every view renders as the
  removed scene does;
- new Gaussians seed the hole's surface (engine.complete.finetune.hole_gaussians: the inpainted depth of the
  views with the largest holes, or the removed renders' depth where an inpainting has none), kept by the same
  test, because densification only grows from what is already movable.

Where the removed scene hides a Gaussian in a view (its depth beyond `occluding_depths` there by more than
`HIDDEN_SLACK`), that view says nothing about it: the hole's back wall is seen through the hole in some views and
hidden in the rest, and only the first say where it renders. Hidden means behind what stops HIDDEN_ALPHA of the light,
not behind the surface a render shows (where opacity passes one half): a capture's background seen through the base
training's haze passes one half at the haze, so the buildings behind the statue capture's figure counted as hidden in
the views that saw them through it, became movable, and the completion retrained them: its test views changed 5.5-6.7%
of their pixels outside the holes, 91-96% of those more than 16 px from any hole (kept 29.5-30.2 dB against the
removed scene in three of four views; 4f9a245, `docs/results/capture/statue.json`).
"""

from __future__ import annotations

import numpy as np
import torch

from engine.capture.scene import Scene
from engine.formats.cameras import Camera, project, sample_nearest
from engine.io.gaussians import PARAM_NAMES, Gaussians

HIDDEN_SLACK = 1.05  # a Gaussian this much deeper than what occludes it in a view is hidden there
HIDDEN_ALPHA = 0.95  # what occludes: the depth where a view's accumulated opacity passes this (a Gaussian behind it
# gives a pixel at most a twentieth of its colour)
NEAR = 1e-3
FIT_ALPHA = 0.1  # fit_to_holes: a Gaussian's visible ellipse is where its alpha reaches this
FIT_SHARE = 0.5  # at least this share of it in the hole (one centred on the hole's edge has half)
FIT_LADDER = tuple(0.85 ** k for k in range(13))  # the scale factors tried, 1 down to 0.14
ELLIPSE_POINTS = 16


@torch.no_grad()
def occluding_depths(gaussians: Gaussians, cameras: list[Camera], device: torch.device) -> dict[int, np.ndarray]:
    """Each view's z-depth at which the accumulated opacity of `gaussians` (the removed scene) passes HIDDEN_ALPHA,
    inf where it never does (nothing there hides anything): what hole_bound's `depths` are (see the module
    docstring for why not the rendered surface)."""
    from engine.render.rasterize import CameraTensors, default_backend
    from engine.render.surface_depth import surface_depth

    on_device = {k: v.to(device) for k, v in gaussians.items()}
    depths = {}
    for i, camera in enumerate(cameras):
        depth = surface_depth(on_device, CameraTensors.from_camera(camera, device), default_backend(device),
                              level=HIDDEN_ALPHA)[0]
        depths[i] = depth.float().cpu().numpy()
    return depths


def hole_bound(means: np.ndarray, scene: Scene, holes: dict[int, np.ndarray],
               depths: dict[int, np.ndarray]) -> np.ndarray:
    """Which `means` (N, 3) render into the holes (view -> bool mask) and nowhere else (see the module
    docstring); `depths` are the removed scene's occluding_depths of the same views."""
    inside_some = np.zeros(len(means), bool)
    outside_any = np.zeros(len(means), bool)
    for i, hole in holes.items():
        u, v, z = project(scene.cameras[i], means)
        in_hole, in_image = sample_nearest(hole, u, v)
        in_image &= z > NEAR
        surface, _ = sample_nearest(depths[i], u, v)
        shown = ~(np.isfinite(surface) & (surface > 0)) | (z <= surface * HIDDEN_SLACK)
        inside_some |= in_image & in_hole
        outside_any |= in_image & ~in_hole & shown
    return inside_some & ~outside_any


def changeable(gaussians: Gaussians, scene: Scene, holes: dict[int, np.ndarray],
               depths: dict[int, np.ndarray]) -> np.ndarray:
    """Which of the removed scene's Gaussians a completion may change or replace: those hole_bound by their centre
    whose visible ellipse also fits the holes at their own size (fit_to_holes). Why not the centre alone: a wide
    one centred in the hole paints past it as well, and changed or dropped it changes the views around the hole
    (tiny CPU runs of training seeds 0-4, Init from scratch grafted: worst view outside the holes against the
    removed renders 38.2-43.4 dB with the wide ones kept; dropped, 27.5 on seed 2. Warm on seed 0, the kept part
    against the removed scene: Ref-fsr 54.6 -> 60.7 dB, Init-fsr 55.2 -> 62.5, m-PSNR 23.37 -> 23.43, 23.42 ->
    23.49)."""
    bound = hole_bound(gaussians["means"].numpy(), scene, holes, depths)
    rows = np.flatnonzero(bound)
    _, fits = fit_to_holes({k: v[rows] for k, v in gaussians.items()}, scene, holes, ladder=(1.0,))
    bound[rows[~fits]] = False
    return bound


def fit_to_holes(gaussians: Gaussians, scene: Scene, holes: dict[int, np.ndarray],
                 ladder: tuple[float, ...] = FIT_LADDER) -> tuple[Gaussians, np.ndarray]:
    """`gaussians` shrunk to render into the holes (view -> bool mask), and which of them could be: each keeps
    the largest of the scale factors in `ladder` at which, in every view where its centre falls in a hole, at least
    FIT_SHARE of its visible ellipse (where its alpha reaches FIT_ALPHA) lies in that hole (past the image's edge
    counts as outside: a Gaussian wider than the view has all of its ellipse there), and in every view whose frame
    its centre lies past, what of that ellipse reaches into the image lies in the hole; those that fit at none are
    False. Why shrink rather than drop: a scene trained from scratch on a tiny or blurred view paints a hole with
    a few Gaussians wider than it (one 107 px wide at opacity 0.97 in a 96 px view hazed every view when grafted
    whole), and dropping them drops the fill with them (tiny CPU runs of training seeds 0-4, Init from scratch: the
    painted fill carried into the part no view saw at 0.55 / 0.49 / 0.54 / 0.48 / 0.77 of the unfilled hole's
    error; 0.55 / 1.00 / 1.04 on seeds 0-2 with the wide ones dropped)."""
    scales = torch.exp(gaussians["scales"].float())
    opacity = torch.sigmoid(gaussians["opacities"].float()).reshape(-1)
    reach = torch.sqrt(2.0 * torch.log((opacity / FIT_ALPHA).clamp_min(1.0)))  # Mahalanobis radius at FIT_ALPHA
    factor = np.zeros(len(scales))
    todo = np.arange(len(scales))
    for shrink in sorted(ladder, reverse=True):  # the largest factor that fits: each tried only down to it
        if not len(todo):
            break
        fits = _fits_in_views(gaussians, scales * shrink, opacity, reach, todo, scene, holes)
        factor[fits] = shrink
        todo = np.setdiff1d(todo, fits)
    shrunk = dict(gaussians)
    shrunk["scales"] = gaussians["scales"] + torch.log(torch.as_tensor(np.maximum(factor, 1e-6)).float())[:, None]
    return shrunk, factor > 0


def _fits_in_views(gaussians: Gaussians, scales: torch.Tensor, opacity: torch.Tensor, reach: torch.Tensor,
                   rows: np.ndarray, scene: Scene, holes: dict[int, np.ndarray]) -> np.ndarray:
    """The `rows` of `gaussians` (at `scales`, activated, and `opacity`) that pass _fits_in_view in every view of
    `holes`; each view tests only those that passed the views before it."""
    for i, hole in holes.items():
        if not len(rows):
            break
        index = torch.as_tensor(rows)
        activated = {"means": gaussians["means"][index], "quats": gaussians["quats"][index],
                     "scales": scales[index], "opacities": opacity[index]}
        rows = rows[_fits_in_view(activated, reach[index], scene.cameras[i], hole)]
    return rows


def _fits_in_view(activated: Gaussians, reach: torch.Tensor, camera, hole: np.ndarray) -> np.ndarray:
    """fit_to_holes' test in one view, on activated scales and opacities: the ellipse at Mahalanobis radius `reach`
    (ELLIPSE_POINTS on it) against the hole, as the rasterizer projects it."""
    from engine.render.rasterize import CameraTensors
    from engine.render.rasterize_reference import project as project_gaussians

    view = CameraTensors.from_camera(camera, "cpu")
    z, centre, conics, _ = project_gaussians(activated["means"].float(), activated["quats"].float(),
                                             activated["scales"], activated["opacities"], view.viewmat, view.K,
                                             camera.width, camera.height, NEAR, 1e10, 0.3)
    axes = _ellipse_axes(conics)
    angles = torch.linspace(0.0, 2.0 * np.pi, ELLIPSE_POINTS + 1)[:-1]
    circle = torch.stack([angles.cos(), angles.sin()], -1)
    rim = centre[:, None, :] + reach[:, None, None] * (circle[None] @ axes.transpose(1, 2))
    in_hole, in_image = sample_nearest(hole, rim[..., 0].numpy(), rim[..., 1].numpy())
    in_hole &= in_image
    centre_in, centre_seen = sample_nearest(hole, centre[:, 0].numpy(), centre[:, 1].numpy())
    ahead = z.numpy() > NEAR
    fits = ~(centre_in & centre_seen & ahead) | (in_hole.mean(axis=1) >= FIT_SHARE)
    return fits & (~(~centre_seen & ahead) | (in_hole | ~in_image).all(axis=1))  # reaching in from past the frame


def _ellipse_axes(conics: torch.Tensor) -> torch.Tensor:
    """(N, 2, 2) matrices A with A A^T the 2D covariance of each conic (the inverse covariance's three entries), from
    the conic's eigenvectors in float64. Why not a Cholesky factor of the inverted conic: a long, thin Gaussian
    projects to a conic whose determinant float32 rounds to zero or below (gsplat then culls it), and the factoring
    stopped every completion of three `_s8`/`_s90` scenes on the GPU (`linalg.cholesky`, not positive-definite). A
    direction the conic does not bound gets an axis of 1e6 px, so such a Gaussian fits no hole."""
    a, b, c = torch.nan_to_num(conics.double(), nan=0.0, posinf=0.0, neginf=0.0).unbind(-1)
    curvature, vectors = torch.linalg.eigh(torch.stack([a, b, b, c], -1).reshape(-1, 2, 2))
    return (vectors / curvature.clamp_min(1e-12).sqrt()[:, None, :]).float()


def split_at_hole(gaussians: Gaussians, movable: np.ndarray) -> tuple[Gaussians, Gaussians]:
    """(movable, fixed) parts of `gaussians` by the boolean `movable`."""
    keep = torch.as_tensor(movable)
    return ({k: gaussians[k][keep].float() for k in PARAM_NAMES},
            {k: gaussians[k][~keep].float() for k in PARAM_NAMES})


def nothing_to_train(start: Gaussians, views: list[int], holes_root) -> str | None:
    """Why a warm completion has nothing to train, or None. Why not an error: the hole masks are only what no view
    saw behind the removed object, and a small object, or one every view saw round, can leave none in any training
    view; the removed scene is then the finished scene, and the user's `complete` ends with it instead of failing
    at the pipeline's last command (the README path's test did so on CI's 2 cores)."""
    if not views:
        return no_hole(holes_root)
    if len(start["means"]) == 0:
        return (f"nothing renders into the holes in {holes_root} and no inpainted surface lies there: the removed "
                "scene is the result")
    return None


def no_hole(holes_root) -> str:
    """The reason a completion has nothing to fill where no training view has a hole."""
    return (f"no training view has a hole in {holes_root}: every view saw behind the object, so the removed scene "
            "is the result")
