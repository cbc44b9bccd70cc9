"""Check on a GPU that the CPU reference rasterizer agrees with gsplat (images and gradients).

    python benchmarks/rasterizer_agreement.py --scene DIR [--out results.json]

Gaussians are initialised from the scene's points with seeded random rotations, anisotropic scales,
opacities, SH and identities; both back ends render the same views in float32 on the GPU, and a fixed
random weighting of every output channel is back-propagated through each. Also compares the torch
fallbacks of gsplat's MCMC ops (engine.train.gsplat_cpu) with the CUDA kernels, and gsplat's views rendered in one
call (render_views) with each rendered alone. Engine Python; needs CUDA.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import torch

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from engine.base.versions import code_commit  # noqa: E402
from engine.capture.scene import load_scene  # noqa: E402
from engine.io.gaussians import init_from_points  # noqa: E402
from engine.render.rasterize import CameraTensors, render, render_views  # noqa: E402


def random_gaussians(scene, device, seed: int = 0) -> dict[str, torch.Tensor]:
    g = init_from_points(scene.points, scene.colors, sh_degree=3, init_opacity=0.5, seed=seed)
    gen = torch.Generator().manual_seed(seed)
    n = len(g["means"])
    g["quats"] = torch.randn(n, 4, generator=gen)
    g["scales"] = g["scales"] + 0.5 * torch.randn(n, 3, generator=gen)
    g["opacities"] = torch.randn(n, generator=gen)
    g["shN"] = 0.1 * torch.randn(g["shN"].shape, generator=gen)
    return {k: v.to(device).requires_grad_(True) for k, v in g.items()}


def compare(scene, views: list[int], device) -> dict:
    params = random_gaussians(scene, device)
    result = {"images": {}, "gradients": {}}
    grads = {}
    for backend in ("gsplat", "reference"):
        for p in params.values():
            p.grad = None
        gen = torch.Generator(device=device).manual_seed(1)
        total, outputs = 0.0, []
        for i in views:
            out = render(params, CameraTensors.from_camera(scene.cameras[i], device), 3, backend=backend)
            weights = [torch.rand(t.shape, generator=gen, device=device) for t in (out.rgb, out.identity, out.alpha)]
            total = total + (out.rgb * weights[0]).sum() + (out.identity * weights[1]).sum() + \
                (out.alpha * weights[2]).sum() + (out.depth * out.alpha.detach()).sum()
            outputs.append(out)
        total.backward()
        grads[backend] = {k: p.grad.detach().clone() for k, p in params.items()}
        result["images"][backend] = outputs
    for name in ("rgb", "alpha", "identity", "depth"):
        a = torch.stack([getattr(o, name) for o in result["images"]["gsplat"]])
        b = torch.stack([getattr(o, name) for o in result["images"]["reference"]])
        mask = torch.stack([o.alpha for o in result["images"]["gsplat"]]) > 0.5 if name == "depth" else ...
        diff = (a - b)[mask].abs()
        result[name] = {"max_abs": float(diff.max()), "mean_abs": float(diff.mean()), "scale": float(b.abs().max())}
    for key in params:
        a, b = grads["gsplat"][key].flatten(), grads["reference"][key].flatten()
        result["gradients"][key] = {
            "max_abs_diff": float((a - b).abs().max()), "max_abs": float(b.abs().max()),
            "rel_l2": float((a - b).norm() / b.norm().clamp_min(1e-30)),
            "cosine": float(torch.nn.functional.cosine_similarity(a, b, dim=0)),
        }
    del result["images"]
    return result


def compare_batched(scene, views: list[int], device) -> dict:
    """gsplat's views in one call (render_views, what a step of several views renders) against each alone:
    images and gradients."""
    params = random_gaussians(scene, device)
    cameras = [CameraTensors.from_camera(scene.cameras[i], device) for i in views]
    gen = torch.Generator(device=device).manual_seed(1)
    weights = [torch.rand(cameras[0].height, cameras[0].width, 3, generator=gen, device=device) for _ in cameras]
    result = {}
    for way, render_all in (("together", lambda: render_views(params, cameras, 3, backend="gsplat")),
                            ("alone", lambda: [render(params, c, 3, backend="gsplat") for c in cameras])):
        for p in params.values():
            p.grad = None
        outs = render_all()
        sum((o.rgb * w).sum() + o.identity.sum() for o, w in zip(outs, weights, strict=True)).backward()
        result[way] = (torch.stack([o.rgb.detach() for o in outs]), params["means"].grad.clone())
    (a, ga), (b, gb) = result["together"], result["alone"]
    return {"rgb_max_abs": float((a - b).abs().max()), "means_grad_rel_l2": float((ga - gb).norm() / gb.norm())}


def compare_mcmc_ops(device) -> dict:
    import gsplat
    from gsplat.relocation import compute_relocation as cuda_relocation

    from engine.train.gsplat_cpu import compute_relocation, quat_scale_to_covar_preci

    gen = torch.Generator().manual_seed(2)
    n, n_max = 10_000, 51
    opac = torch.rand(n, generator=gen).to(device) * 0.98 + 0.01
    scales = torch.rand(n, 3, generator=gen).to(device) + 0.01
    ratios = torch.randint(1, n_max, (n,), generator=gen).to(device)
    binoms = torch.zeros(n_max, n_max, device=device)
    for i in range(n_max):
        for k in range(i + 1):
            binoms[i, k] = float(__import__("math").comb(i, k))
    o1, s1 = cuda_relocation(opac, scales, ratios.clone(), binoms)
    o2, s2 = compute_relocation(opac, scales, ratios.clone(), binoms)
    quats = torch.randn(n, 4, generator=gen).to(device)
    c1, _ = gsplat.quat_scale_to_covar_preci(quats, scales, compute_preci=False, triu=False)
    c2, _ = quat_scale_to_covar_preci(quats, scales, compute_preci=False)
    return {"relocation_opacity_max_rel": float(((o1 - o2).abs() / o1.abs()).max()),
            "relocation_scale_max_rel": float(((s1 - s2).abs() / s1.abs()).max()),
            "covariance_max_abs": float((c1 - c2).abs().max())}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", required=True)
    parser.add_argument("--views", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--out", default="")
    args = parser.parse_args()
    if not torch.cuda.is_available():
        print("error: this check needs CUDA (it compares against gsplat's kernels)", file=sys.stderr)
        return 2
    device = torch.device("cuda")
    scene = load_scene(args.scene)
    result = {"scene": args.scene, "gaussians": len(scene.points), "size": [scene.cameras[0].width,
                                                                           scene.cameras[0].height],
              "device": torch.cuda.get_device_name(), "commit": code_commit(), **compare(scene, args.views, device),
              "mcmc_ops": compare_mcmc_ops(device), "batched_views": compare_batched(scene, args.views, device)}
    text = json.dumps(result, indent=1)
    print(text)
    if args.out:
        Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
