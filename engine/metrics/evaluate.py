"""Evaluate a trained scene on the test views: PSNR, SSIM against images/, identity mIoU against masks/
(None for a scene without masks, such as a user's capture: JSON has no NaN, and there is nothing to score)."""

from __future__ import annotations

import torch

from engine.capture.scene import Scene
from engine.io.gaussians import Gaussians
from engine.metrics.image_metrics import IoUCounter, psnr, ssim
from engine.render.rasterize import CameraTensors, render


@torch.no_grad()
def evaluate_views(scene: Scene, views: list[int], gaussians: Gaussians, classifier: torch.nn.Module,
                   sh_degree: int, device: torch.device) -> dict[str, float | None]:
    psnrs, ssims, seen_psnrs = [], [], {}
    num_classes = classifier.out_features
    iou = IoUCounter(num_classes)
    for i in views:
        out = render(gaussians, CameraTensors.from_camera(scene.cameras[i], device), sh_degree,
                     classifier=classifier, depth=False)
        target = torch.as_tensor(scene.images[i], device=device).float() / 255.0
        image = out.rgb.clamp(0, 1)
        psnrs.append(psnr(image, target))
        if i in scene.unseen and not scene.unseen[i].all():
            seen = torch.as_tensor(~scene.unseen[i], device=device)
            seen_psnrs[scene.cameras[i].name] = round(psnr(image[seen], target[seen]), 2)
        ssims.append(float(ssim(image, target)))
        if scene.masks is not None:
            labels = out.logits.argmax(-1)
            iou.add(labels, torch.as_tensor(scene.masks[i]).clamp(max=num_classes - 1))
    mean = sum(psnrs) / max(len(psnrs), 1)
    return {"psnr": mean, "ssim": sum(ssims) / max(len(ssims), 1),
            "identity_miou": iou.miou() if scene.masks is not None else None, "views": len(views),
            # floaters show as one view far below the others (a haze band, a cloud at a table's edge)
            "psnr_per_view": {scene.cameras[i].name: round(p, 2) for i, p in zip(views, psnrs, strict=True)},
            "worst_view_gap": _worst_gap(psnrs), **_seen_only(seen_psnrs)}


def _worst_gap(psnrs: list[float]) -> float | None:
    """How far the worst view lies below the views' mean."""
    return round(sum(psnrs) / len(psnrs) - min(psnrs), 2) if psnrs else None


def _seen_only(per_view: dict[str, float]) -> dict:
    """The same over the pixels some training view saw, where the scene marks the others (a generated scene's
    unseen/): sky past every training view's frame is no floater, and no training can know it (the statue's worst
    view: 6.4 dB below the mean over all pixels, 2.6 over the seen ones; docs/BENCHMARKS.md, "Training")."""
    if not per_view:
        return {}
    return {"psnr_seen_per_view": per_view, "worst_view_gap_seen": _worst_gap(list(per_view.values()))}
