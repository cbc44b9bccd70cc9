"""Issue 17's worst-view lead, measured before any plumbing: a base run at the defaults trained and evaluated with
gsplat's `antialiased` rasterize mode (Mip-Splatting's 2D filter: each Gaussian's opacity scaled by
sqrt(det(cov2d) / det(cov2d + 0.3 I))) against the classic mode the engine uses. The test views that fall furthest
below the mean show fine texture far away at grazing angles (docs/BENCHMARKS.md, "Which test views fall furthest
below the mean"), which is what that filter is for. The mode is switched for this process only, by wrapping the
engine's one gsplat entry point; the run's metrics.json holds the per-view PSNR as `engine train` writes it.

    python docs/benchmarks/train/antialias/train_aa.py SCENE OUT {antialiased|classic} [engine train flags]

Not a product option yet: a model trained so renders differently in the standard 3DGS viewers (Blender's add-ons
draw the classic mode), so it becomes one only if it measures better, with the reference rasterizer matched.
"""

import functools
import json
import sys

from engine.render import rasterize
from engine.train.config import TrainConfig
from engine.train.run import train

scene, out, mode, *flags = sys.argv[1:]
if mode not in ("antialiased", "classic"):
    sys.exit("mode: antialiased or classic")
original = rasterize.gsplat_rasterization  # loads gsplat on first use (the CPU path never does)
rasterize.gsplat_rasterization = lambda: functools.partial(original(), rasterize_mode=mode)
config = TrainConfig(scene=scene, out=out, device="cuda")
for name, value in zip(flags[::2], flags[1::2], strict=True):
    field = name.lstrip("-").replace("-", "_")
    setattr(config, field, type(getattr(config, field))(value))
metrics = train(config)
print(json.dumps({"mode": mode, "psnr": round(metrics["psnr"], 3), "worst_view_gap": metrics["worst_view_gap"],
                  "per_view": metrics["psnr_per_view"], "train_seconds": metrics.get("train_seconds")}))
