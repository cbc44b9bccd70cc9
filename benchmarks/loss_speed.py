"""How long the training's photometric loss takes, forward and backward, for a step's views as one batch: laid
out as the loss lays it out on this device, copied channels first (NCHW-contiguous), and as a permuted view of the
render's (B, H, W, C), channels last in memory: the SSIM blur's grouped convolution picks its CUDA kernel by layout
(docs/BENCHMARKS.md, "Training": with the permuted view a cuDNN NHWC engine took 3.3 ms a step).

    python benchmarks/loss_speed.py [--views 4] [--size 480 640] [--repeats 200]

Engine Python; meant for the GPU machine (on the CPU it times the CPU's kernels). Prints one JSON line.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import torch

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import engine.train.photometric_loss as loss_module  # noqa: E402
from engine.base.device import pick_device  # noqa: E402
from engine.base.versions import gpu_name  # noqa: E402


def seconds_per_call(rgb: torch.Tensor, target: torch.Tensor, repeats: int) -> float:
    """Mean seconds of one forward and backward pass, synchronised at both ends of the loop."""
    for _ in range(10):  # warm-up: kernel choice and caches
        loss_module.photometric_loss(rgb, target, 0.2).backward()
    if rgb.is_cuda:
        torch.cuda.synchronize()
    start = time.perf_counter()
    for _ in range(repeats):
        loss_module.photometric_loss(rgb, target, 0.2).backward()
    if rgb.is_cuda:
        torch.cuda.synchronize()
    return (time.perf_counter() - start) / repeats


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--views", type=int, default=4)
    parser.add_argument("--size", type=int, nargs=2, default=[480, 640])
    parser.add_argument("--repeats", type=int, default=200)
    parser.add_argument("--device", default="auto")
    args = parser.parse_args()
    device = pick_device(args.device)
    gen = torch.Generator().manual_seed(0)
    shape = (args.views, *args.size, 3)
    target = torch.rand(shape, generator=gen).to(device)
    rgb = torch.rand(shape, generator=gen).to(device).requires_grad_(True)
    as_laid = loss_module._channels_first
    times = {"as_laid": seconds_per_call(rgb, target, args.repeats)}
    for name, layout in (("nchw_contiguous", lambda view: view.contiguous()), ("channels_last", lambda view: view)):
        loss_module._channels_first = lambda images, layout=layout: layout(
            images.permute(2, 0, 1)[None] if images.dim() == 3 else images.permute(0, 3, 1, 2))
        try:
            times[name] = seconds_per_call(rgb, target, args.repeats)
        finally:
            loss_module._channels_first = as_laid
    print(json.dumps({"views": args.views, "size": args.size, "device": str(device), "gpu": gpu_name(device),
                      "ms_per_call": {k: round(1000 * v, 3) for k, v in times.items()}}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
