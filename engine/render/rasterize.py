"""Render Gaussians for one camera: RGB, expected depth, alpha and identity (or class logits), in one pass.

gsplat 1.5.3 on CUDA; on the CPU the pure-torch reference (engine.render.rasterize_reference) with the same math.
RGB (spherical harmonics: gsplat's kernel on CUDA, engine.render.sh on the CPU) and the identity channels are
blended together, with expected depth appended ("RGB+ED") when asked for, so one rasterization gives everything.

Given the classifier, the Gaussians' identities are projected through its weights *before* blending:
blending is linear, so W (sum_i w_i e_i) + b = sum_i w_i (W e_i) + b, the same logits and gradients
as classifying the blended 16-d map, but with C channels instead of 16. gsplat's kernels exist for
1-5, 8, 9, 16, 17, 32... channels and pad the rest, so RGB + 16 identity + depth costs a 32-channel
pass while RGB + 6 classes costs 9 channels: on the H200 the rasterizer's share of a training step at
290k Gaussians fell from 6.4 ms to 3.3 ms (docs/BENCHMARKS.md). With more classes than identity dimensions the map is
blended first and classified per pixel.
"""

from __future__ import annotations

import contextlib
import functools
import sys
from dataclasses import dataclass

import torch

from engine.formats.cameras import Camera
from engine.io.gaussians import Gaussians
from engine.render.rasterize_reference import rasterize_reference
from engine.render.sh import eval_sh

NEAR_PLANE, FAR_PLANE, EPS2D = 0.01, 1e10, 0.3
# gsplat's tiles of 8x8 pixels instead of its default 16: a trained livingroom state (300k Gaussians, 640x480) renders
# and back-propagates in 2.60 ms instead of 3.13 (RGB) and 3.48 instead of 4.02 (9 channels), H200; a training step
# 0.43 ms shorter; renders and gradients agree with the CPU reference as closely as at 16 (docs/BENCHMARKS.md)
TILE_SIZE = 8


@dataclass
class RenderOutput:
    rgb: torch.Tensor  # (H, W, 3) linear in [0, 1] as trained (the images' sRGB values)
    depth: torch.Tensor | None  # (H, W) expected z-depth, sum(w z) / sum(w); None unless asked for
    alpha: torch.Tensor  # (H, W) accumulated opacity
    identity: torch.Tensor | None  # (H, W, 16) blended identity; None when the logits were blended directly
    logits: torch.Tensor | None  # (H, W, C) classifier logits; None without a classifier
    info: dict  # projection data for densification strategies (means2d, radii, width, height, ...)


@dataclass(frozen=True)
class CameraTensors:
    """A camera on a device: world-to-camera (4, 4), intrinsics (3, 3), centre (3,), size."""

    viewmat: torch.Tensor
    K: torch.Tensor
    center: torch.Tensor
    width: int
    height: int

    @classmethod
    def from_camera(cls, camera: Camera, device: torch.device | str) -> CameraTensors:
        def tensor(a):
            return torch.as_tensor(a, dtype=torch.float32, device=device)

        return cls(tensor(camera.world_to_camera), tensor(camera.K), tensor(camera.center), camera.width,
                   camera.height)


def default_backend(device: torch.device | str) -> str:
    return "gsplat" if torch.device(device).type == "cuda" else "reference"


@functools.cache
def gsplat_rasterization():
    """gsplat's rasterization, its CUDA extension built or loaded first with its messages ("gsplat: CUDA
    extension has been set up ...") sent to stderr: stdout carries the add-on's JSON lines."""
    with contextlib.redirect_stdout(sys.stderr):
        from gsplat import rasterization
        from gsplat.cuda._backend import _C  # noqa: F401  -- the build happens here, on first use
    return rasterization


@functools.cache
def gsplat_spherical_harmonics():
    """gsplat's SH evaluation, loaded after its extension is (gsplat_rasterization)."""
    gsplat_rasterization()
    from gsplat.cuda._wrapper import spherical_harmonics

    return spherical_harmonics


def sh_colors(gaussians: Gaussians, offsets: torch.Tensor, sh_degree: int, backend: str) -> torch.Tensor:
    """Each Gaussian's SH colour (N, 3), before the +0.5 offset, towards `offsets` (N, 3: Gaussian minus camera
    centre, not normalised). gsplat evaluates it in one kernel each way; our broadcast product (engine.render.sh,
    the same constants) takes about 40 small kernels forward, which cost the training loop 0.6 ms of host time a
    step, so it serves the CPU reference only."""
    sh0, sh_rest = gaussians["sh0"], gaussians["shN"]
    if backend == "gsplat":
        coeffs = torch.cat([sh0, sh_rest[:, : (sh_degree + 1) ** 2 - 1]], dim=1)
        return gsplat_spherical_harmonics()(sh_degree, offsets, coeffs)
    return eval_sh(sh_degree, sh0, sh_rest, torch.nn.functional.normalize(offsets, dim=-1))


def view_colours(gaussians: Gaussians, camera: CameraTensors, sh_degree: int, backend: str) -> torch.Tensor:
    """Each Gaussian's RGB (N, 3) as `camera` sees it: its SH colour towards the camera, offset and clamped at 0
    as 3DGS renders it."""
    offsets = gaussians["means"].detach() - camera.center
    return torch.clamp_min(sh_colors(gaussians, offsets, sh_degree, backend) + 0.5, 0.0)


def rasterize(gaussians: Gaussians, features: torch.Tensor, camera: CameraTensors, backend: str,
              depth: bool = True) -> tuple[torch.Tensor, torch.Tensor, dict]:
    """Blend per-Gaussian `features` (N, D) into (H, W, D [+ 1 expected depth]) and alpha (H, W, 1) on
    either back end: rasterize_views of one camera, which every render here goes through."""
    colors, alphas, info = rasterize_views(gaussians, features[None], [camera], backend, depth)
    return colors[0], alphas[0], info


def rasterize_views(gaussians: Gaussians, features: torch.Tensor, cameras: list[CameraTensors], backend: str,
                    depth: bool = True) -> tuple[torch.Tensor, torch.Tensor, dict]:
    """`rasterize` for C cameras of one size at once, `features` (C, N, D) one set a camera: (C, H, W, D [+ 1]),
    (C, H, W, 1) and one info for the C views (gsplat's, (C, N, ...)). gsplat blends them in one call, one set of
    launches for all C: a training step is bound by the host's launches, not by pixels (at 320x240 a step took
    what it takes at 640x480; docs/BENCHMARKS.md, "Training"). The reference renders them one by one."""
    args = (gaussians["means"], gaussians["quats"], torch.exp(gaussians["scales"]),
            torch.sigmoid(gaussians["opacities"]))
    width, height = cameras[0].width, cameras[0].height
    if any((c.width, c.height) != (width, height) for c in cameras):
        raise ValueError("rasterize_views takes cameras of one size")
    if backend == "gsplat":
        return gsplat_rasterization()(
            *args, features, torch.stack([c.viewmat for c in cameras]), torch.stack([c.K for c in cameras]), width,
            height, near_plane=NEAR_PLANE, far_plane=FAR_PLANE, eps2d=EPS2D, sh_degree=None, packed=False,
            tile_size=TILE_SIZE, render_mode="RGB+ED" if depth else "RGB")
    views = [rasterize_reference(*args, view_features, camera.viewmat, camera.K, width, height, NEAR_PLANE,
                                 FAR_PLANE, EPS2D) for view_features, camera in zip(features, cameras, strict=True)]
    colors = torch.stack([c if depth else c[..., :-1] for c, _, _ in views])
    infos = [info for _, _, info in views]  # one view's as it is: DefaultStrategy reads its means2d's gradient
    info = infos[0] if len(infos) == 1 else infos[0] | {
        "n_cameras": len(infos), **{key: torch.cat([i[key] for i in infos]) for key in ("means2d", "radii", "depths")}}
    return colors, torch.stack([a for _, a, _ in views]), info


def render(gaussians: Gaussians, camera: CameraTensors, sh_degree: int, backend: str | None = None,
           classifier: torch.nn.Linear | None = None, depth: bool = True, identity: bool = True) -> RenderOutput:
    """Render `gaussians` (see engine.io.gaussians) seen by `camera`, using SH bands up to `sh_degree`;
    with `classifier`, also the per-pixel class logits; `depth=False` skips the depth channel; `identity=False`
    blends RGB alone (a training step with no identity loss: 3 channels instead of 9 or 19)."""
    return render_views(gaussians, [camera], sh_degree, backend, classifier, depth, identity)[0]


def render_views(gaussians: Gaussians, cameras: list[CameraTensors], sh_degree: int, backend: str | None = None,
                 classifier: torch.nn.Linear | None = None, depth: bool = True,
                 identity: bool = True) -> list[RenderOutput]:
    """`render` for several cameras, in one rasterization where they share a size (rasterize_views; each output's
    info is the batch's, (C, N, ...)), else one a camera."""
    if len({(c.width, c.height) for c in cameras}) > 1:
        return [render_views(gaussians, [c], sh_degree, backend, classifier, depth, identity)[0] for c in cameras]
    means = gaussians["means"]
    backend = backend or default_backend(means.device)
    rgbs = [view_colours(gaussians, c, sh_degree, backend) for c in cameras]
    rgb = rgbs[0][None] if len(rgbs) == 1 else torch.stack(rgbs)  # one view: no copy
    features, project_first = rgb, False
    if identity:
        encoding = gaussians["identity"]
        project_first = classifier is not None and classifier.out_features <= encoding.shape[-1]
        blended = encoding @ classifier.weight.T if project_first else encoding
        features = torch.cat([rgb, blended[None].expand(len(cameras), -1, -1)], dim=-1)
    colors, alphas, info = rasterize_views(gaussians, features, cameras, backend, depth)
    return [_output(view_colors, view_alphas, info, classifier, depth, identity, project_first)
            for view_colors, view_alphas in zip(colors, alphas, strict=True)]


def _output(colors: torch.Tensor, alphas: torch.Tensor, info: dict, classifier: torch.nn.Linear | None, depth: bool,
            identity: bool, project_first: bool) -> RenderOutput:
    """One view's RenderOutput from its blended channels: RGB, then identity or logits, then depth."""
    channels = colors[..., 3:-1] if depth else colors[..., 3:]
    if not identity:
        blended_identity, logits = None, None
    elif project_first:
        blended_identity, logits = None, channels + classifier.bias
    else:
        blended_identity = channels
        logits = classifier(channels) if classifier is not None else None
    return RenderOutput(rgb=colors[..., :3], depth=colors[..., -1] if depth else None, alpha=alphas[..., 0],
                        identity=blended_identity, logits=logits, info=info)
