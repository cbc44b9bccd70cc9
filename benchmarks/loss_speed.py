"""How long the training's photometric loss takes, forward and backward, for a step's views as one batch, with the
batch as the loss lays it out (channels last: the render's (B, H, W, C) permuted) and copied channels first
(NCHW-contiguous): the SSIM blur's grouped convolution picks its CUDA kernel by layout (docs/BENCHMARKS.md,
"Training": at 640x480 and four views a cuDNN NHWC engine took 3.3 ms a step where one view at a time took 1.0).

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
    times = {"channels_last": seconds_per_call(rgb, target, args.repeats)}
    loss_module._channels_first = lambda images: as_laid(images).contiguous()
    try:
        times["nchw_contiguous"] = seconds_per_call(rgb, target, args.repeats)
    finally:
        loss_module._channels_first = as_laid
    print(json.dumps({"views": args.views, "size": args.size, "device": str(device), "gpu": gpu_name(device),
                      "ms_per_call": {k: round(1000 * v, 3) for k, v in times.items()}}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
