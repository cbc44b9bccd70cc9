"""Check our LPIPS and FID against the `lpips` and `pytorch-fid` packages, given the same weights.

    python benchmarks/metrics_agreement.py [--results DIR]     # where torchvision imports (the GPU machine)

No weights can be downloaded, so both sides get the same random weights: torchvision's alexnet(weights=None)
saved under torchvision's file name, and our FID Inception's random initialisation (batch-norm statistics
measured on images, so that features do not vanish) saved as
pt_inception-2015-12-05-6726825d.pth in a temporary TORCH_HOME, where pytorch-fid's loader finds it
without downloading. Compared: LPIPS values and maps on smooth random image pairs; pool3 features; FID
from pytorch-fid's calculate_frechet_distance (scipy's sqrtm) against ours (singular values), on more images
than features so that scipy's sqrtm is well-posed. Writes docs/results/cpu/metrics_agreement.json.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
from benchmarks.records import provenance  # noqa: E402


def smooth_images(n: int, size: tuple[int, int], seed: int):
    import torch
    import torch.nn.functional as F

    g = torch.Generator().manual_seed(seed)
    coarse = torch.rand(n, 3, size[0] // 8, size[1] // 8, generator=g)
    fine = 0.1 * torch.rand(n, 3, *size, generator=g)
    return (F.interpolate(coarse, size=size, mode="bicubic", align_corners=False) + fine).clamp(0, 1)


def check_lpips(home: Path, device: str) -> dict:
    import lpips
    import torch
    import torchvision

    from engine.metrics.lpips_metric import Lpips

    torch.manual_seed(0)
    state = torchvision.models.alexnet(weights=None).state_dict()
    backbone = home / "alexnet-owt-7be5be79.pth"
    torch.save(state, backbone)
    theirs = lpips.LPIPS(net="alex", pnet_rand=True, verbose=False)
    slices = {0: 1, 3: 2, 6: 3, 8: 4, 10: 5}
    theirs.net.load_state_dict({f"slice{slices[i]}.{i}.{p}": state[f"features.{i}.{p}"] for i in slices
                                for p in ("weight", "bias")})
    theirs = theirs.to(device).eval()
    ours = Lpips(str(backbone)).to(device)
    a, b = smooth_images(16, (128, 160), 1).to(device), smooth_images(16, (128, 160), 2).to(device)
    with torch.no_grad():
        value_theirs = theirs(a, b, normalize=True).flatten()
        map_theirs = lpips.LPIPS(net="alex", pnet_rand=True, spatial=True, verbose=False).to(device).eval()
        map_theirs.net.load_state_dict(theirs.net.state_dict())
        spatial_theirs = map_theirs(a, b, normalize=True)[:, 0]
    return {"lpips_max_abs_diff": float((ours(a, b) - value_theirs).abs().max()),
            "lpips_map_max_abs_diff": float((ours.map(a, b) - spatial_theirs).abs().max()),
            "lpips_mean": float(value_theirs.mean())}


def check_fid(home: Path, device: str) -> dict:
    import numpy as np
    import torch
    from pytorch_fid.inception import InceptionV3

    from engine.metrics.distribution_metrics import frechet_distance
    from engine.metrics.fid_inception import WEIGHTS_FILE, FidInception

    torch.manual_seed(0)
    checkpoints = home / "hub" / "checkpoints"
    checkpoints.mkdir(parents=True, exist_ok=True)
    calibrated = FidInception(load=False)  # random weights; batch-norm statistics from real activations, so
    for module in calibrated.modules():    # that features keep their scale through the 94 layers
        if isinstance(module, torch.nn.BatchNorm2d):
            module.reset_running_stats()
            module.momentum = None
    calibrated.train()(smooth_images(64, (96, 128), 7))
    torch.save(calibrated.state_dict(), checkpoints / WEIGHTS_FILE)
    ours = FidInception(str(checkpoints / WEIGHTS_FILE)).to(device)
    theirs = InceptionV3([3], resize_input=True, normalize_input=True).to(device).eval()
    feats = {"ours_a": [], "ours_b": [], "theirs_a": [], "theirs_b": []}
    with torch.no_grad():
        for k in range(0, 2200, 200):
            for side, seed in (("a", k), ("b", 100_000 + k)):
                images = smooth_images(200, (96, 128), seed).to(device)
                if side == "b":
                    images = (images * 0.8 + 0.1).clamp(0, 1)  # another distribution
                feats[f"ours_{side}"].append(ours(images).double().cpu())
                feats[f"theirs_{side}"].append(theirs(images)[0][:, :, 0, 0].double().cpu())
    f = {k: torch.cat(v).numpy() for k, v in feats.items()}
    stats = [(x.mean(0), np.cov(x, rowvar=False)) for x in (f["theirs_a"], f["theirs_b"])]
    fid_theirs = scipy_frechet_distance(*stats[0], *stats[1])
    return {"feature_max_abs_diff": float(np.abs(f["ours_a"] - f["theirs_a"]).max()),
            "feature_scale": float(np.abs(f["theirs_a"]).mean()),
            "fid_pytorch_fid": fid_theirs, "fid_ours": frechet_distance(f["ours_a"], f["ours_b"]),
            "fid_ours_on_their_features": frechet_distance(f["theirs_a"], f["theirs_b"]), "images_per_set": 2200}


def scipy_frechet_distance(mu1, sigma1, mu2, sigma2) -> float:
    """pytorch-fid's calculate_frechet_distance, whose sqrtm(..., disp=False) call newer scipy rejects."""
    import numpy as np
    from scipy import linalg

    covmean = linalg.sqrtm(sigma1.dot(sigma2))
    if not np.isfinite(covmean).all():
        offset = np.eye(sigma1.shape[0]) * 1e-6
        covmean = linalg.sqrtm((sigma1 + offset).dot(sigma2 + offset))
    diff = mu1 - mu2
    return float(diff.dot(diff) + np.trace(sigma1) + np.trace(sigma2) - 2 * np.trace(covmean.real))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--results", default=str(REPO / "docs" / "results" / "cpu"))
    args = parser.parse_args()
    import torch

    device = "cuda" if torch.cuda.is_available() else "cpu"
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["TORCH_HOME"] = tmp
        record = {**check_lpips(Path(tmp), device), **check_fid(Path(tmp), device), **provenance()}
    out = Path(args.results) / "metrics_agreement.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(record, indent=1))
    print(json.dumps(record, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
