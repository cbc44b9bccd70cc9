"""Training settings: one dataclass, defaults that work on the GPU (30k steps), and a small CPU preset.

The CLI is generated from the fields (engine.base.config_cli), and the resolved config is saved as config.json in
the run folder, so every number can be traced to its settings.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from engine.base.errors import InputError
from engine.train.camera_clearance import FULL_SIGMAS, SIGMAS

PRESETS: dict[str, dict] = {
    # Gaussian Grouping's schedule (refine every 100 from 500 to 15k, reset opacity every 3k) and its
    # losses, on gsplat's MCMCStrategy at a 300k budget (max_gaussians).
    "default": {},
    # A few hundred steps at tiny sizes for CPU tests: densify early and often (DefaultStrategy: a few
    # thousand points grow to what the tiny views need), no opacity reset, and identities on every step (the CPU
    # rasterizer's cost does not follow the channel count, so skipping them saves nothing there).
    "tiny": dict(steps=200, max_gaussians=0, sh_degree=1, sh_degree_interval=100, refine_start=50, refine_stop=150,
                 refine_every=50, reset_every=100_000, checkpoint_every=100, log_every=10, reg3d_refresh=100,
                 identity_every=1, camera_clearance=SIGMAS),  # the core only: its 128 px walls stand near the cameras
}

COLOUR_MODELS = ("off", "gain", "affine")  # engine.train.view_colours
MAX_VIEWS_PER_STEP = 8  # Adam's beta1 at B views a step is 1 - B (1 - 0.9) (gsplat's trainer): 0.2 at 8
# views a step where the run keeps the default's length and a budget: a step is bound by the host (launches, syncs;
# 5.2 ms at 320x240 as at 640x480), and gsplat renders the four in one call: 37-40% less time at equal test PSNR
# and identity mIoU on four families (docs/BENCHMARKS.md, "Decisions")
VIEWS_PER_STEP = 4
SCHEDULE = ("refine_start", "refine_stop", "reset_every")  # steps that scale with the run's length
BACKGROUNDS = ("black", "random")


@dataclass
class TrainConfig:
    """One training run's settings (Gaussian Grouping's losses and schedule on gsplat). Why each default is what it
    is: docs/BENCHMARKS.md, "Decisions"."""

    scene: str = ""  # the scene folder (COLMAP model, images/, masks/ where there are any)
    out: str = ""  # a new run folder
    preset: str = "default"  # default | tiny (a few hundred steps at tiny sizes, for CPU tests)
    steps: int = 30_000  # training steps (left at 30k with a budget: 7,500 of 4 views); the schedule stretches
    seed: int = 0  # random seed of the initialisation and the view order
    device: str = "auto"  # auto | cuda | cpu
    max_gaussians: int = 300_000  # MCMC budget (gsplat's MCMCStrategy); 0: no budget (gsplat's DefaultStrategy)
    resolution: int = 1  # load the scene at 1/resolution of its size (1, 2, 4, 8), as 3DGS's -r
    sh_degree: int = 3  # spherical-harmonics degree of the colours
    sh_degree_interval: int = 1000  # one more SH band every this many steps (0: every band from the start)
    init_opacity: float = 0.1  # opacity of the Gaussians made from the sparse points
    lr_means: float = 1.6e-4  # learning rate of the positions, times the scene's extent (gsplat's simple_trainer)
    lr_means_final_ratio: float = 0.01  # the positions' rate decays to this share of itself by the last step
    lr_quats: float = 1e-3  # learning rate of the rotations
    lr_scales: float = 5e-3  # learning rate of the log scales
    lr_opacities: float = 5e-2  # learning rate of the opacity logits
    lr_sh0: float = 2.5e-3  # learning rate of the base colour
    lr_shN: float = 2.5e-3 / 20  # learning rate of the higher SH bands
    lr_identity: float = 2.5e-3  # learning rate of the 16-d identity encodings (Gaussian Grouping)
    lr_classifier: float = 5e-4  # learning rate of the per-pixel linear classifier
    ssim_weight: float = 0.2  # photometric loss: (1 - w) L1 + w (1 - SSIM)
    fused_ssim: bool = False  # the SSIM term by the fussim package's CUDA kernel (a measured lead; CUDA only)
    views_per_step: int = 0  # views a step, losses averaged (MCMC only); 0: 4 at the default steps and a budget, else 1
    colour_correction: str = "off"  # off | gain | affine: a correction per training view (engine.train.view_colours)
    # random: a dark photo is matched only by opacity, never by seeing through. On the CPU at 1/8 size (1,500 steps,
    # 30k budget) it lost, 18.98 against 23.28 dB; the skull capture's 14.5 dB on an H200 was Gaussians holding the
    # cameras (engine.train.camera_clearance: 20.57 dB with black), not its transparency
    background: str = "black"  # black | random: behind the Gaussians in a training view (random: a colour a view)
    camera_clearance: float = FULL_SIGMAS  # Gaussians whose ellipsoid holds a training camera at this many sigma are
    # emptied before each refinement and at the end (engine.train.camera_clearance; 0: never; the tiny preset: 1)
    background_floaters: float = 0.0  # empty at the end what changes no training view by this (0-1 colour; 0: off)
    # where it is drawn, over the black background (engine.train.background_floaters: the skull capture's flat test
    # views); off until measured on the GPU
    lr_colours: float = 1e-3  # learning rate of the per-view colour corrections
    identity_weight: float = 1.0  # weight of the identity cross-entropy (divided by log of the class count)
    identity_every: int = 8  # render and train the identities on every Nth step only (1: every step, the paper's)
    reg3d_every: int = 5  # the 3D KNN regulariser runs on every Nth identity step
    reg3d_k: int = 5  # neighbours each sampled Gaussian's identity is pulled towards
    reg3d_samples: int = 1000  # Gaussians sampled for the regulariser each time
    reg3d_weight: float = 2.0  # weight of the 3D regulariser
    reg3d_pool: int = 2048  # Gaussians whose neighbour lists are kept (renewed every reg3d_refresh steps)
    reg3d_refresh: int = 200  # steps between renewals of the regulariser's neighbour pool
    refine_start: int = 500  # first densification step
    refine_stop: int = 15_000  # last densification step
    refine_every: int = 100  # steps between densifications
    reset_every: int = 3000  # steps between opacity resets (DefaultStrategy only)
    mcmc_opacity_reg: float = 0.01  # MCMC's opacity regulariser
    mcmc_scale_reg: float = 0.01  # MCMC's scale regulariser
    checkpoint_every: int = 5000  # steps between checkpoints (a stopped run resumes from the newest)
    keep_checkpoints: int = 2  # checkpoints kept on disk
    log_every: int = 100  # steps between progress lines

    @classmethod
    def from_saved(cls, values: dict) -> TrainConfig:
        """A run's saved config.json. Runs saved while the colour correction was on or off stored a bool."""
        colour = values.get("colour_correction", "off")
        if isinstance(colour, bool):
            values = {**values, "colour_correction": "affine" if colour else "off"}
        return cls(**values)

    def sh_degree_at(self, step: int) -> int:
        """SH bands in use after `step` steps: one more every sh_degree_interval, up to sh_degree (0: every band
        from the start, for a run that begins from a trained scene and may take no step)."""
        if self.sh_degree_interval <= 0:
            return self.sh_degree
        return min(step // self.sh_degree_interval, self.sh_degree)

    def resolved(self) -> TrainConfig:
        """Apply the preset's values to fields the user left at their defaults. A schedule the user left
        alone stretches with --steps: densifying stops at the same fraction of the run whatever its length
        (the tiny preset at 300 steps densifies until 225, not 150; a 10k-step run stops at 5k, not past
        its end)."""
        if self.preset not in PRESETS:
            raise InputError(f"unknown preset {self.preset!r}: choose from {', '.join(sorted(PRESETS))}")
        if self.background not in BACKGROUNDS:
            raise InputError(f"unknown --background {self.background!r}: choose from {', '.join(BACKGROUNDS)}")
        if self.colour_correction not in COLOUR_MODELS:
            raise InputError(f"unknown --colour-correction {self.colour_correction!r}: choose from "
                             f"{', '.join(COLOUR_MODELS)}")
        defaults = TrainConfig()
        preset = PRESETS[self.preset]
        if not self.views_per_step:
            return dataclasses.replace(self, views_per_step=self.auto_views()).resolved()
        untouched = tuple(k for k in SCHEDULE if getattr(self, k) == getattr(defaults, k))
        changes = {k: v for k, v in preset.items() if getattr(self, k) == getattr(defaults, k)}
        planned = dataclasses.replace(self, **{**changes, "steps": preset.get("steps", defaults.steps)})
        steps = changes.get("steps", self.steps)
        if self.views_per_step == 1:
            return planned.with_steps(steps, untouched)
        return self._batched(planned, steps if self.steps != defaults.steps else steps // self.views_per_step,
                             untouched)

    def auto_views(self) -> int:
        """The views a step `views_per_step` 0 stands for: VIEWS_PER_STEP (a quarter of the steps) where the run
        keeps the default's 30k steps and a budget, as measured; else 1, so that `--steps N` stays N steps of one
        view, as every run before, and DefaultStrategy (no budget, the tiny preset) its one view a step."""
        preset = PRESETS.get(self.preset, {})
        budget = self.max_gaussians if self.max_gaussians != TrainConfig.max_gaussians else preset.get(
            "max_gaussians", self.max_gaussians)
        default_length = self.steps == TrainConfig.steps and "steps" not in preset
        return VIEWS_PER_STEP if default_length and budget > 0 else 1

    def _batched(self, planned: TrainConfig, steps: int, untouched: tuple[str, ...]) -> TrainConfig:
        """`planned` at `views_per_step` B views a step, as gsplat's trainer runs a batch (its steps_scaler 1/B):
        the steps (where the user left them), the schedule, densification's interval and the SH bands' at 1/B,
        so the run sees as many views and densifies as often per view seen."""
        batch = self.views_per_step
        if not 1 <= batch <= MAX_VIEWS_PER_STEP:
            raise InputError(f"--views-per-step {batch}: choose 1 to {MAX_VIEWS_PER_STEP} (Adam's first moment "
                             "decays as 1 - B (1 - 0.9))")
        if self.max_gaussians <= 0:
            raise InputError("--views-per-step above 1 needs a budget (--max-gaussians N, gsplat's MCMC): "
                             "DefaultStrategy's gradient statistics are per view")
        defaults = TrainConfig()
        per_view = {k: max(1, round(getattr(planned, k) / batch)) for k in ("refine_every", "sh_degree_interval")
                    if getattr(self, k) == getattr(defaults, k)}
        return dataclasses.replace(planned, **per_view).with_steps(steps, untouched)

    def one_view_a_step(self) -> TrainConfig:
        """This resolved config at one view a step, as many views seen: B views a step for S steps become B S
        steps, with densification's interval and the SH bands' stretched by B (`_batched` undone). A completion
        trains from its base run's config with its own steps and, for FT, no budget, which several views a
        step refuse (DefaultStrategy's statistics are per view)."""
        batch = self.views_per_step
        if batch == 1:
            return self
        return dataclasses.replace(self, views_per_step=1, refine_every=self.refine_every * batch,
                                   sh_degree_interval=self.sh_degree_interval * batch).with_steps(self.steps * batch)

    def with_steps(self, steps: int, schedule: tuple[str, ...] = SCHEDULE) -> TrainConfig:
        """This config run for `steps` steps, its schedule stretched or shrunk to match (a completion that
        retrains for fewer steps than its base run still stops densifying before its end)."""
        scale = steps / self.steps
        return dataclasses.replace(self, steps=steps, **{k: max(1, round(getattr(self, k) * scale)) for k in schedule})
