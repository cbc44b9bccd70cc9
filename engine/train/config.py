"""Training settings: one dataclass, defaults that work on the GPU (30k steps), and a small CPU preset.

The CLI is generated from the fields (engine.cli), and the resolved config is saved as config.json in
the run folder, so every number can be traced to its settings.
"""

from __future__ import annotations

import argparse
import dataclasses
from dataclasses import dataclass

from engine.base.errors import InputError

PRESETS: dict[str, dict] = {
    # Gaussian Grouping's schedule (refine every 100 from 500 to 15k, reset opacity every 3k) and its
    # losses, on gsplat's MCMCStrategy at a 300k budget (max_gaussians).
    "default": {},
    # A few hundred steps at tiny sizes for CPU tests: densify early and often (DefaultStrategy: a few
    # thousand points grow to what the tiny views need), no opacity reset.
    "tiny": dict(steps=200, max_gaussians=0, sh_degree=1, sh_degree_interval=100, refine_start=50, refine_stop=150,
                 refine_every=50, reset_every=100_000, checkpoint_every=100, log_every=10, reg3d_refresh=100,
                 identity_every=1),
}

SCHEDULE = ("refine_start", "refine_stop", "reset_every")  # steps that scale with the run's length


@dataclass
class TrainConfig:
    scene: str = ""
    out: str = ""
    preset: str = "default"
    steps: int = 30_000
    seed: int = 0
    device: str = "auto"  # auto | cuda | cpu
    # N = gsplat's MCMCStrategy capped at N Gaussians; 0 = no budget (gsplat's DefaultStrategy). Chosen from the
    # budget curve at 640x480/100 views (docs/BENCHMARKS.md, "The budget curve"): test PSNR 41.3-44.1 dB from
    # 50k to 1M on livingroom, completions flat across budgets, 1M about 1.5x the time; unbudgeted runs leave
    # floaters (a livingroom test view 11.7 dB below the mean)
    max_gaussians: int = 300_000
    resolution: int = 1  # load the scene at 1/resolution of its size (1, 2, 4, 8), as 3DGS's -r
    sh_degree: int = 3
    sh_degree_interval: int = 1000  # one more SH band every this many steps
    init_opacity: float = 0.1
    # learning rates (gsplat simple_trainer / Gaussian Grouping); means scaled by the scene extent
    lr_means: float = 1.6e-4
    lr_means_final_ratio: float = 0.01
    lr_quats: float = 1e-3
    lr_scales: float = 5e-3
    lr_opacities: float = 5e-2
    lr_sh0: float = 2.5e-3
    lr_shN: float = 2.5e-3 / 20
    lr_identity: float = 2.5e-3
    lr_classifier: float = 5e-4
    # losses (Gaussian Grouping): 0.8 L1 + 0.2 (1 - SSIM) + CE / log(C) + 3D regulariser
    ssim_weight: float = 0.2
    identity_weight: float = 1.0
    # render and train the identities (and the 3D regulariser) on every Nth step only, RGB alone in between (3
    # rasterized channels, not 9); Gaussian Grouping's is every step (1). On the GPU (livingroom 640x480/100
    # views, 30k steps, one training each): N = 1 / 2 / 4 trained in 207 / 180 / 169 s to test PSNR 42.90 /
    # 42.86 / 42.88 and identity mIoU 0.995 each (docs/BENCHMARKS.md). The tiny preset keeps 1: at a few
    # hundred steps N=2 cost 0.018 mIoU, and the CPU rasterizer saves nothing. Scenes without masks never
    # render identities: nothing would train them.
    identity_every: int = 4
    reg3d_every: int = 5
    reg3d_k: int = 5
    reg3d_samples: int = 1000
    reg3d_weight: float = 2.0
    # neighbour lists of a pool of Gaussians, rebuilt after each densification and every reg3d_refresh
    # steps: a rebuild searches all Gaussians (8192 queries: 64 ms at 290k on the H200, 0.6 ms a step
    # while densifying every 100 steps); 2048 queries, renewed every 200 steps, cost a quarter of that
    reg3d_pool: int = 2048
    reg3d_refresh: int = 200
    # densification
    refine_start: int = 500
    refine_stop: int = 15_000
    refine_every: int = 100
    reset_every: int = 3000
    mcmc_opacity_reg: float = 0.01
    mcmc_scale_reg: float = 0.01
    # bookkeeping
    checkpoint_every: int = 5000
    keep_checkpoints: int = 2
    log_every: int = 100

    def sh_degree_at(self, step: int) -> int:
        """SH bands in use after `step` steps: one more every sh_degree_interval, up to sh_degree."""
        return min(step // self.sh_degree_interval, self.sh_degree)

    def resolved(self) -> TrainConfig:
        """Apply the preset's values to fields the user left at their defaults. A schedule the user left
        alone stretches with --steps: densifying stops at the same fraction of the run whatever its length
        (the tiny preset at 300 steps densifies until 225, not 150; a 10k-step run stops at 5k, not past
        its end)."""
        if self.preset not in PRESETS:
            raise InputError(f"unknown preset {self.preset!r}: choose from {', '.join(sorted(PRESETS))}")
        defaults = TrainConfig()
        preset = PRESETS[self.preset]
        untouched = tuple(k for k in SCHEDULE if getattr(self, k) == getattr(defaults, k))
        changes = {k: v for k, v in preset.items() if getattr(self, k) == getattr(defaults, k)}
        planned = dataclasses.replace(self, **{**changes, "steps": preset.get("steps", defaults.steps)})
        return planned.with_steps(changes.get("steps", self.steps), untouched)

    def with_steps(self, steps: int, schedule: tuple[str, ...] = SCHEDULE) -> TrainConfig:
        """This config run for `steps` steps, its schedule stretched or shrunk to match (a completion that
        retrains for fewer steps than its base run still stops densifying before its end)."""
        scale = steps / self.steps
        return dataclasses.replace(self, steps=steps, **{k: max(1, round(getattr(self, k) * scale)) for k in schedule})


def add_config_arguments(parser: argparse.ArgumentParser, cls=TrainConfig, skip: tuple[str, ...] = (),
                         required: tuple[str, ...] = ("scene", "out")) -> None:
    """One --option per dataclass field, typed from its default (bools as --x/--no-x, lists of numbers)."""
    for f in dataclasses.fields(cls):
        if f.name in skip:
            continue
        flag = f"--{f.name.replace('_', '-')}"
        if f.default_factory is not dataclasses.MISSING:
            parser.add_argument(flag, type=float, nargs="*", default=f.default_factory(), help="(default: none)")
        elif isinstance(f.default, bool):
            parser.add_argument(flag, action=argparse.BooleanOptionalAction, default=f.default,
                                help=f"(default: {f.default})")
        else:
            parser.add_argument(flag, type=type(f.default), default=f.default, required=f.name in required,
                                help=f"(default: {f.default})")


def config_from_args(args: argparse.Namespace, cls=TrainConfig):
    return cls(**{f.name: getattr(args, f.name) for f in dataclasses.fields(cls) if hasattr(args, f.name)})
