"""Forward+backward cost of one render at a given Gaussian count: one joint pass or RGB and identity apart.

    python scripts/bench_render.py --scene DIR [--gaussians 300000] [--iters 50]

gsplat compiles kernels for 1-5, 8, 9, 16, 17, 32, 33, ... channels and pads other counts, so our joint
20 channels (RGB + 16 identity + depth) run as 32; two passes run as 4 and 16. Engine Python; CUDA.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import torch

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from engine.io.scene import load_scene  # noqa: E402
from engine.render.rasterize import CameraTensors  # noqa: E402


def gaussians_like(scene, n: int, device) -> dict[str, torch.Tensor]:
    gen = torch.Generator().manual_seed(0)
    base = torch.as_tensor(scene.points, dtype=torch.float32)
    pick = torch.randint(len(base), (n,), generator=gen)
    return {"means": base[pick] + 0.01 * torch.randn(n, 3, generator=gen), "quats": torch.randn(n, 4, generator=gen),
            "scales": torch.full((n, 3), -5.0) + 0.3 * torch.randn(n, 3, generator=gen),
            "opacities": torch.randn(n, generator=gen), "colors": torch.rand(n, 19, generator=gen)}


def timed(fn, iters: int) -> float:
    for _ in range(5):
        fn()
    torch.cuda.synchronize()
    start = time.perf_counter()
    for _ in range(iters):
        fn()
    torch.cuda.synchronize()
    return (time.perf_counter() - start) / iters * 1000


def main() -> int:
    from gsplat import rasterization

    parser = argparse.ArgumentParser()
    parser.add_argument("--scene", required=True)
    parser.add_argument("--gaussians", type=int, default=300_000)
    parser.add_argument("--iters", type=int, default=50)
    args = parser.parse_args()
    device = torch.device("cuda")
    scene = load_scene(args.scene)
    cam = CameraTensors.from_camera(scene.cameras[0], device)
    g = {k: v.to(device).requires_grad_(True) for k, v in gaussians_like(scene, args.gaussians, device).items()}

    def raster(colors, mode):
        return rasterization(g["means"], g["quats"], torch.exp(g["scales"]), torch.sigmoid(g["opacities"]), colors,
                             cam.viewmat[None], cam.K[None], cam.width, cam.height, sh_degree=None, packed=False,
                             render_mode=mode)[0]

    def joint():
        raster(g["colors"], "RGB+ED").square().mean().backward()

    def separate():
        (raster(g["colors"][:, :3], "RGB+ED").square().mean()
         + raster(g["colors"][:, 3:], "RGB").square().mean()).backward()

    def rgb_only():
        raster(g["colors"][:, :3], "RGB+ED").square().mean().backward()

    for name, fn in (("joint 20 (padded to 32)", joint), ("separate 4 + 16", separate), ("RGB+ED only", rgb_only)):
        print(f"{args.gaussians} Gaussians, {cam.width}x{cam.height}, {name}: {timed(fn, args.iters):.2f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
