"""Gaussian Grouping training on gsplat: one loop; densification is a gsplat strategy plugged into it.

Losses (Gaussian Grouping): 0.8 L1 + 0.2 (1 - SSIM) + CE(classifier(identity map), mask) / log(C)
+ every 5 steps the 3D identity regulariser. No budget: gsplat's DefaultStrategy; a budget
(--max-gaussians N): gsplat's MCMCStrategy capped at N (engine.train.strategies), with its opacity and
scale regularisers.
"""

from __future__ import annotations

import dataclasses
import math
import random
from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import torch

from engine.base.errors import InputError
from engine.capture.scene import Scene
from engine.io.gaussians import PARAM_NAMES, Gaussians, concat, init_from_points, new_classifier
from engine.metrics.image_metrics import psnr_from_mse
from engine.render.rasterize import CameraTensors, render_views
from engine.train.adam_step import AdamState, adam_step
from engine.train.camera_clearance import centres_of, empty_camera_holders
from engine.train.config import TrainConfig
from engine.train.identity_regularizer import IdentityRegularizer
from engine.train.photometric_loss import photometric_loss
from engine.train.strategies import BudgetStrategy, GrowStrategy, make_strategy
from engine.train.view_colours import ViewColours


def scene_extent(scene: Scene) -> float:
    """gsplat's scene scale: 1.1 x the largest camera distance from the cameras' mean centre."""
    centers = np.stack([c.center for c in scene.cameras])
    return float(np.linalg.norm(centers - centers.mean(0), axis=1).max() * 1.1)


def num_classes_of(scene: Scene) -> int:
    if scene.masks is None:
        return 1
    ids = [int(m.max()) for m in scene.masks] + [o.id for o in scene.objects]
    return max(ids) + 1


def pixel_cross_entropy(logits: torch.Tensor, labels: torch.Tensor) -> torch.Tensor:
    """Mean cross-entropy of logits (..., C) against integer labels (...), as F.cross_entropy computes it.

    Why not F.cross_entropy: its NLL kernels reduce in a single block, 0.37 ms a step (forward and
    backward) for a 640x480 map on the H200; logsumexp minus a gather is a few plain kernels.
    """
    picked = logits.gather(-1, labels[..., None])[..., 0]
    return (torch.logsumexp(logits, dim=-1) - picked).mean()


@dataclass
class StepResult:
    """Tensors on the device: reading them waits for the GPU, so the loop reads them only when logging."""

    loss: torch.Tensor
    rgb: torch.Tensor
    target: torch.Tensor

    @property
    def psnr(self) -> float:
        return psnr_from_mse(float(((self.rgb.clamp(0, 1) - self.target) ** 2).mean()))


class GroupingObjective:
    """Gaussian Grouping's loss: 0.8 L1 + 0.2 (1 - SSIM), the identity cross-entropy over log C, every
    reg3d_every steps the 3D regulariser, and with a budget MCMC's opacity and scale regularisers."""

    needs_depth = False

    def __call__(self, trainer: Trainer, view: int, out, target: torch.Tensor) -> torch.Tensor:
        cfg = trainer.config
        with trainer.part("photometric"):
            photometric = photometric_loss(out.rgb, target, cfg.ssim_weight, cfg.fused_ssim)
        return photometric + grouping_terms(trainer, view, out)

    def views_loss(self, trainer: Trainer, views: list[int], outs: list, targets: list[torch.Tensor]
                   ) -> torch.Tensor:
        """The mean of __call__ over a step's views, in fewer launches: the photometric loss of views of one size
        as one batch, MCMC's regularisers (the same for every view) once. Why: a step of four views is bound by
        the host's launches, and the photometric loss four times over was the most of them (an H200 at 300k
        Gaussians, 640x480: 14.8 ms a step against 8.6 ms of kernels, 511 launches; in one batch 11.8 ms, 269
        launches; docs/BENCHMARKS.md, "Training"). The identity terms stay per view: each view has its own masks,
        and the 3D regulariser draws its own sample for each."""
        cfg = trainer.config
        with trainer.part("photometric"):
            if len({out.rgb.shape for out in outs}) == 1:
                photometric = photometric_loss(torch.stack([out.rgb for out in outs]), torch.stack(targets),
                                               cfg.ssim_weight, cfg.fused_ssim)
            else:
                photometric = sum(photometric_loss(out.rgb, target, cfg.ssim_weight, cfg.fused_ssim)
                                  for out, target in zip(outs, targets, strict=True)) / len(outs)
        identity = [identity_terms(trainer, view, out) for view, out in zip(views, outs, strict=True)]
        with trainer.part("strategy"):
            return photometric + sum(identity) / len(identity) + trainer.strategy.regularisation(trainer.params, cfg)


def grouping_terms(trainer: Trainer, view: int, out) -> torch.Tensor | float:
    """The identity and regulariser terms every objective keeps."""
    loss = identity_terms(trainer, view, out)
    with trainer.part("strategy"):
        return loss + trainer.strategy.regularisation(trainer.params, trainer.config)


def identity_terms(trainer: Trainer, view: int, out) -> torch.Tensor | float:
    """The identity cross-entropy against the view's masks and the 3D regulariser, on the steps that render
    identities; 0 on the others."""
    cfg, step, loss = trainer.config, trainer.step_index, 0.0
    if out.logits is not None:  # a step that renders identities (scenes with masks, every identity_every steps)
        classes = out.logits.shape[-1]
        with trainer.part("identity"):
            loss = loss + (cfg.identity_weight * pixel_cross_entropy(out.logits, trainer.masks[view])
                           / math.log(classes))
        if cfg.reg3d_every > 0 and step % cfg.reg3d_every == 0:
            with trainer.part("regulariser"):
                loss = loss + trainer.regularizer.loss(trainer.params["identity"], trainer.classifier,
                                                       trainer.params["means"], step, trainer.generator)
    return loss


def batch_adam(views: int, eps: float) -> dict:
    """Adam's betas and eps at `views` views a step, as gsplat's trainer sets them for a batch (one view: torch's)."""
    if views == 1:
        return {"eps": eps}
    return {"eps": eps / math.sqrt(views), "betas": (1 - views * (1 - 0.9), 1 - views * (1 - 0.999))}


def no_part(name: str) -> AbstractContextManager:
    """A training step's parts are named for a profiler (benchmarks/train_profile.py sets Trainer.part to
    torch.profiler.record_function); in training they cost one empty context each."""
    return nullcontext()


def trained_part(info: dict, fixed: int) -> dict:
    """The rasterizer's per-Gaussian info for the trained Gaussians alone (the rendered ones after the first
    `fixed`), as a densification strategy sized to the parameters reads it: its 2D means with their gradient
    and its radii (packed=False: (cameras, N, ...))."""
    if not fixed:
        return info
    means2d = info["means2d"]
    trained = means2d.detach()[:, fixed:]
    if means2d.retains_grad and means2d.grad is not None:  # DefaultStrategy asked for it (MCMC never does)
        trained.grad = means2d.grad[:, fixed:]
    return info | {"means2d": trained, "radii": info["radii"][:, fixed:]}


class Objective(Protocol):
    needs_depth: bool

    def __call__(self, trainer: Trainer, view: int, out, target: torch.Tensor) -> torch.Tensor: ...


class Trainer:
    """Holds the parameters, optimizers and strategy state of one run; `step()` advances it by one view."""

    def __init__(self, config: TrainConfig, scene: Scene, device: torch.device, start: Gaussians | None = None,
                 fixed: Gaussians | None = None, objective: Objective | None = None, views: list[int] | None = None,
                 classifier: torch.nn.Linear | None = None) -> None:
        """`start`: Gaussians to begin from instead of the sparse points. `fixed`: Gaussians rendered with them
        every step that never change: they are not parameters, so no optimizer, densification, relocation or
        position noise reaches them, and the run's scene is both sets (`gaussians`). `objective` replaces
        Gaussian Grouping's loss; `views` restricts the training views that are drawn; `classifier` starts from
        a trained identity classifier instead of a random one. These are the completion methods' plug-ins
        (engine.complete.finetune, engine.complete.hole_region)."""
        if config.views_per_step < 1:  # 0 is the CLI's "auto", which TrainConfig.resolved settles
            raise ValueError("a Trainer takes a resolved TrainConfig (views_per_step 0 is unresolved)")
        self.config, self.scene, self.device = config, scene, device
        self.fixed = None if fixed is None else {k: fixed[k].float().to(device) for k in PARAM_NAMES}
        self.objective = objective or GroupingObjective()
        self.train_views = views if views is not None else scene.train
        self.strategy: BudgetStrategy | GrowStrategy = make_strategy(config)
        if isinstance(self.strategy, BudgetStrategy) and device.type != "cuda":
            from engine.train.gsplat_cpu import enable_cpu_mcmc

            enable_cpu_mcmc()
        torch.manual_seed(config.seed)
        self.views = np.random.default_rng(config.seed)
        self.generator = torch.Generator().manual_seed(config.seed)
        self.order: list[int] = []
        self.extent = scene_extent(scene)
        self.params = self._init_params(start)
        self.optimizers = {name: self._adam(name, p) for name, p in self.params.items()}
        self.classifier = (classifier or new_classifier(num_classes_of(scene))).to(device)
        self.classifier_opt = AdamState(self.classifier.parameters(), lr=config.lr_classifier * self._batch_lr,
                                        **batch_adam(config.views_per_step, 1e-8))
        self.strategy.check_sanity(self.params, self.optimizers)
        self.strategy_state = self.strategy.start(self.extent)
        self.regularizer = IdentityRegularizer(k=config.reg3d_k, samples=config.reg3d_samples,
                                               weight=config.reg3d_weight, pool_size=config.reg3d_pool,
                                               refresh_every=config.reg3d_refresh)
        self.cameras = [CameraTensors.from_camera(c, device) for c in scene.cameras]
        self.camera_centres = centres_of([scene.cameras[i] for i in self.train_views], device)
        self.camera_holders = torch.zeros((), dtype=torch.long, device=device)  # emptied so far (camera_clearance)
        self.images = {i: torch.as_tensor(scene.images[i], device=device) for i in scene.train}
        self.masks = ({i: torch.as_tensor(scene.masks[i], device=device).long() for i in scene.train}
                      if scene.masks is not None else None)
        self.colours = (ViewColours(self.train_views, device, config.lr_colours, config.colour_correction)
                        if config.colour_correction != "off" else None)
        self.step_index = 0
        self.seconds = 0.0
        self.part: Callable[[str], AbstractContextManager] = no_part  # names a step's parts for a profiler

    def _init_params(self, start: Gaussians | None) -> torch.nn.ParameterDict:
        cfg = self.config
        if start is not None:
            return self._parameters(start)
        points, colors = self.scene.points, self.scene.colors
        cap = self.strategy.cap
        if cap and len(points) > cap:  # a strategy that never removes starts within its cap
            keep = np.random.default_rng(cfg.seed).choice(len(points), cap, replace=False)
            points, colors = points[keep], colors[keep]
        init_opacity = self.strategy.init_opacity or cfg.init_opacity
        return self._parameters(init_from_points(points, colors, cfg.sh_degree, init_opacity, cfg.seed))

    def _parameters(self, tensors: Gaussians) -> torch.nn.ParameterDict:
        return torch.nn.ParameterDict({k: torch.nn.Parameter(tensors[k].to(self.device)) for k in PARAM_NAMES})

    def _adam(self, name: str, param: torch.nn.Parameter) -> AdamState:
        lr = getattr(self.config, f"lr_{name}") * (self.extent if name == "means" else 1.0)
        return AdamState([param], lr=lr * self._batch_lr, **batch_adam(self.config.views_per_step, 1e-15), name=name)

    @property
    def _batch_lr(self) -> float:
        """Learning rates at B views a step: sqrt(B) times (gsplat's trainer)."""
        return math.sqrt(self.config.views_per_step)

    def _next_view(self) -> int:
        if not self.order:
            self.order = [int(i) for i in self.views.permutation(self.train_views)]
        return self.order.pop()

    def _means_lr(self, step: int) -> float:
        cfg = self.config
        return cfg.lr_means * self.extent * self._batch_lr * cfg.lr_means_final_ratio ** (step / max(cfg.steps, 1))

    def step(self) -> StepResult:
        """One training step on `views_per_step` training views (their losses averaged). Its parts are named
        (`part`) so that a profile can say where a step's time goes (docs/BENCHMARKS.md, "Training")."""
        part, step = self.part, self.step_index
        with part("data"):
            lr = self._means_lr(step)
            self.optimizers["means"].param_groups[0]["lr"] = lr
            identity = self.masks is not None and step % self.config.identity_every == 0
        outs, targets, loss = self._views_loss(identity)
        out, target = outs[-1], targets[-1]
        with part("strategy"):
            self.strategy.step_pre_backward(self.params, self.optimizers, self.strategy_state, step, out.info)
        with part("backward"):
            loss.backward()
        with part("optimizer"):
            adam_step((*self.optimizers.values(), self.classifier_opt,
                       *(() if self.colours is None else (self.colours.optimizer,))))
            if self.colours is not None:
                self.colours.recentre()
        with part("strategy"):  # MCMC (the only strategy at several views a step) reads no view's info
            if self.config.camera_clearance > 0 and (step % self.config.refine_every == 0  # before it relocates
                                                     or step + 1 == self.config.steps):  # or prunes; at the end
                self.camera_holders += empty_camera_holders(self.params, self.camera_centres,
                                                            self.config.camera_clearance)
            self.strategy.after_backward(self.params, self.optimizers, self.strategy_state, step,
                                         trained_part(out.info, self.fixed_count), lr)
        self.step_index += 1
        return StepResult(loss=loss.detach(), rgb=out.rgb.detach(), target=target)

    def _views_loss(self, identity: bool):
        """The step's training views rendered (in one rasterization where they share a size: a step is bound
        by the host's launches, engine.render.rasterize.rasterize_views), their photos and the mean of their
        losses (in one batch where the objective has `views_loss`)."""
        part = self.part
        with part("data"):
            views = [self._next_view() for _ in range(self.config.views_per_step)]
            targets = [self.images[view].float() / 255.0 for view in views]
        with part("render"):
            outs = render_views(self._rendered(), [self.cameras[view] for view in views], self.sh_degree,
                                classifier=self.classifier, depth=self.objective.needs_depth, identity=identity)
            if self.colours is not None:  # each view's photo's exposure and white balance
                outs = [dataclasses.replace(out, rgb=self.colours(view, out.rgb))
                        for view, out in zip(views, outs, strict=True)]
            if self.config.background == "random":
                outs = [self._on_random_background(out) for out in outs]
        if len(views) > 1 and hasattr(self.objective, "views_loss"):
            return outs, targets, self.objective.views_loss(self, views, outs, targets)
        losses = [self.objective(self, view, out, target)
                  for view, out, target in zip(views, outs, targets, strict=True)]
        return outs, targets, losses[0] if len(losses) == 1 else sum(losses) / len(losses)

    def _on_random_background(self, out):
        """`out` over a colour drawn for this view and step: a photo's dark pixel is then matched only by opaque
        Gaussians of that colour, never by seeing through to a black background (3DGS trainers' random
        background; nerfstudio's splatfacto draws one by default)."""
        colour = torch.rand(3, generator=self.generator).to(out.rgb.device, non_blocking=True)
        return dataclasses.replace(out, rgb=out.rgb + (1.0 - out.alpha[..., None]) * colour)

    @property
    def fixed_count(self) -> int:
        return 0 if self.fixed is None else len(self.fixed["means"])

    @property
    def count(self) -> int:
        """Gaussians in the run's scene, fixed and trained."""
        return self.fixed_count + len(self.params["means"])

    def _rendered(self) -> Gaussians | torch.nn.ParameterDict:
        """What a step renders: the fixed Gaussians first, then the trained ones."""
        if self.fixed is None:
            return self.params
        return concat(self.fixed, self.params)

    @property
    def gaussians(self) -> Gaussians:
        """The run's scene: the fixed Gaussians and the trained ones."""
        return {k: v.detach() for k, v in self._rendered().items()}

    @property
    def sh_degree(self) -> int:
        return self.config.sh_degree_at(self.step_index)

    # --- checkpoints -------------------------------------------------------------------------------------
    def state_dict(self) -> dict:
        return {
            "step": self.step_index, "seconds": self.seconds,
            "params": {k: v.detach().cpu() for k, v in self.params.items()},
            "optimizers": {k: o.state_dict() for k, o in self.optimizers.items()},
            "classifier": self.classifier.state_dict(), "classifier_opt": self.classifier_opt.state_dict(),
            "strategy_state": {k: (v.cpu() if torch.is_tensor(v) else v) for k, v in self.strategy_state.items()},
            "order": list(self.order), "views_rng": self.views.bit_generator.state,
            "generator": self.generator.get_state(), "torch_rng": torch.get_rng_state(),
            "cuda_rng": torch.cuda.get_rng_state() if self.device.type == "cuda" else None,
            "python_rng": random.getstate(), "regularizer": self.regularizer.state_dict(),
            "fixed": self.fixed_count, "objective": type(self.objective).__name__,
            "colours": None if self.colours is None else self.colours.state_dict(),
            "camera_holders": int(self.camera_holders),
        }

    def load_state_dict(self, state: dict) -> None:
        """Continue from a checkpoint. A completion's run (its own objective, fixed Gaussians) resumes only
        with the same plug-ins, which `complete --resume` rebuilds; the checkpoint holds the trained Gaussians
        and the count of fixed ones, which must match."""
        objective = state.get("objective", GroupingObjective.__name__)
        if objective != type(self.objective).__name__ or state.get("fixed", 0) != self.fixed_count:
            raise InputError(f"this checkpoint was trained with {objective} and {state.get('fixed', 0)} fixed "
                             f"Gaussians, not {type(self.objective).__name__} and {self.fixed_count}: a "
                             "completion's run resumes with the same `python -m engine complete` command and "
                             "--resume")
        self.step_index, self.seconds = state["step"], state["seconds"]
        self.params = self._parameters(state["params"])
        self.optimizers = {name: self._adam(name, p) for name, p in self.params.items()}
        for name, optimizer in self.optimizers.items():
            optimizer.load_state_dict(state["optimizers"][name])
        self.classifier.load_state_dict(state["classifier"])
        self.classifier_opt.load_state_dict(state["classifier_opt"])
        if self.colours is not None and state.get("colours") is not None:
            self.colours.load_state_dict(state["colours"])
        self.strategy_state = {k: (v.to(self.device) if torch.is_tensor(v) else v)
                               for k, v in state["strategy_state"].items()}
        self.order = list(state["order"])
        self.camera_holders.fill_(state.get("camera_holders", 0))
        self.views.bit_generator.state = state["views_rng"]
        self.generator.set_state(state["generator"])
        torch.set_rng_state(state["torch_rng"])
        if state["cuda_rng"] is not None and self.device.type == "cuda":
            torch.cuda.set_rng_state(state["cuda_rng"])
        random.setstate(state["python_rng"])
        self.regularizer.load_state_dict(state["regularizer"], self.params["means"])
