"""Forward+backward cost of one render at a given Gaussian count: one joint pass or RGB and identity apart.

    python benchmarks/render_speed.py --scene DIR [--gaussians 300000] [--iters 50]
    python benchmarks/render_speed.py --scene DIR --run RUN [--iters 100]

With --run, the trained Gaussians of RUN's newest checkpoint (benchmarks/train_profile.py --save) render a training
view's RGB (3 channels, the training step between identity steps) and RGB + 6 class logits (9 channels), forward
and backward, at each of gsplat's tile sizes and with packed on and off: options that leave the image as it is
and change only the kernels' work.

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

from engine.capture.scene import load_scene  # noqa: E402
from engine.render.rasterize import EPS2D, NEAR_PLANE, CameraTensors  # noqa: E402


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


def option_sweep(scene, run: Path, iters: int) -> None:
    """Forward + backward of a trained state's render at each tile size, packed and not (see the docstring)."""
    from gsplat import rasterization

    from engine.train.run import latest_checkpoint

    device = torch.device("cuda")
    params = torch.load(latest_checkpoint(run), map_location="cpu", weights_only=False)["params"]
    g = {k: v.to(device) for k, v in params.items()}
    cam = CameraTensors.from_camera(scene.cameras[scene.train[0]], device)
    features = torch.rand(len(g["means"]), 9, device=device, requires_grad=True)
    for channels in (3, 9):
        for packed in (False, True):
            for tile in (8, 16, 32) if channels == 3 else (8, 16):  # 9 channels at 32: too many resources (H200)
                def step(channels=channels, packed=packed, tile=tile):
                    image = rasterization(g["means"], g["quats"], torch.exp(g["scales"]),
                                          torch.sigmoid(g["opacities"]), features[:, :channels], cam.viewmat[None],
                                          cam.K[None], cam.width, cam.height, near_plane=NEAR_PLANE, eps2d=EPS2D,
                                          sh_degree=None, packed=packed, tile_size=tile)[0]
                    image.square().mean().backward()

                print(f"{len(g['means'])} Gaussians, {cam.width}x{cam.height}, {channels} channels, packed={packed}, "
                      f"tile {tile}: {timed(step, iters):.3f} ms", flush=True)


def main() -> int:
    from gsplat import rasterization

    parser = argparse.ArgumentParser()
    parser.add_argument("--scene", required=True)
    parser.add_argument("--run", type=Path, help="sweep gsplat's options on this run's trained Gaussians")
    parser.add_argument("--gaussians", type=int, default=300_000)
    parser.add_argument("--iters", type=int, default=50)
    args = parser.parse_args()
    device = torch.device("cuda")
    scene = load_scene(args.scene)
    if args.run:
        option_sweep(scene, args.run, args.iters)
        return 0
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
