"""One Adam step for all of a run's optimizers, with a handful of host calls.

Why not `optimizer.step()` for each: a training step has eight Adam optimizers (seven Gaussian parameters,
each its own so gsplat's strategies can move its state when Gaussians are added or relocated, plus the
classifier), and each `Adam.step` spends about 0.2 ms of host time in Python (hooks, grouping, checks):
1.6 ms a step on the H200's host, while the update's GPU work is 0.45 ms (docs/BENCHMARKS.md,
"Training"). The host time matters because the loop is bound by it.

The update is torch's own fused Adam kernel (`torch._fused_adam_`, what `Adam(fused=True)` runs), so the
numbers are those of `Adam(fused=True).step()`; parameters with the same hyperparameters share one call,
and every step counter advances in one `_foreach_add_`. The state stays in the optimizers, where gsplat's
strategies and checkpoints find it.

The optimizers are `AdamState`s: what torch.optim.Adam keeps (param_groups, state, state_dict in torch's own
format) without its step machinery, which nothing here calls. Why not torch's class: constructing any
torch.optim.Optimizer imports torch._dynamo on first use, 1.7 s on a CI core (3.3 s under load), in every engine
process that trains (the base run and each benchmark cell); nothing else in those processes imports it.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable

import torch

# the hyperparameters torch.optim.Adam(fused=True) records in each param group (its state_dict carries them)
ADAM_GROUP = {"betas": (0.9, 0.999), "weight_decay": 0.0, "amsgrad": False, "maximize": False, "foreach": None,
              "capturable": False, "differentiable": False, "fused": True, "decoupled_weight_decay": False}


class AdamState:
    """One parameter group's Adam settings and per-parameter state, as torch.optim.Adam holds them (see the
    module docstring); `adam_step` updates them. Checkpoints read and write torch's state_dict format, so runs
    saved with torch's Adam resume here and the other way round."""

    def __init__(self, params: Iterable[torch.Tensor], lr: float, eps: float = 1e-8, **group) -> None:
        self.param_groups = [{"params": list(params), "lr": lr, "eps": eps, **ADAM_GROUP, **group}]
        self.state: defaultdict[torch.Tensor, dict] = defaultdict(dict)

    def state_dict(self) -> dict:
        group = self.param_groups[0]
        params = group["params"]
        return {"state": {i: dict(self.state[p]) for i, p in enumerate(params) if self.state.get(p)},
                "param_groups": [{**{k: v for k, v in group.items() if k != "params"},
                                  "params": list(range(len(params)))}]}

    def load_state_dict(self, saved: dict) -> None:
        """torch.optim.Optimizer.load_state_dict's casts: moments to each parameter's device and dtype, the fused
        step counter to float32 on its device; tensors copied, so the saved dict's stay untouched."""
        group = self.param_groups[0]
        (saved_group,) = saved["param_groups"]
        group.update({k: v for k, v in saved_group.items() if k != "params"})
        self.state = defaultdict(dict)
        for index, param in zip(saved_group["params"], group["params"], strict=True):
            if index in saved["state"]:
                self.state[param] = {k: v.to(param.device, torch.float32 if k == "step" else param.dtype, copy=True)
                                     for k, v in saved["state"][index].items()}  # copies: never shared with `saved`


def _state(optimizer: AdamState, param: torch.Tensor) -> dict:
    """The parameter's Adam state, created as fused Adam creates it (a float32 step on the parameter's device);
    a checkpoint written before adam_step existed keeps the classifier's step on the CPU, moved here."""
    state = optimizer.state[param]
    if not state:
        state["step"] = torch.zeros((), dtype=torch.float32, device=param.device)
        state["exp_avg"] = torch.zeros_like(param, memory_format=torch.preserve_format)
        state["exp_avg_sq"] = torch.zeros_like(param, memory_format=torch.preserve_format)
    elif state["step"].device != param.device:  # from a checkpoint of an unfused Adam, which keeps it on the CPU
        state["step"] = state["step"].to(param.device, torch.float32)
    return state


def adam_step(optimizers: Iterable[AdamState]) -> None:
    """Apply one Adam update to every parameter with a gradient, then drop the gradients (set_to_none)."""
    batches: dict[tuple, list[tuple[torch.Tensor, dict]]] = {}
    for optimizer in optimizers:
        for group in optimizer.param_groups:
            if group["amsgrad"] or group["maximize"] or group.get("decoupled_weight_decay", False):
                raise ValueError("adam_step implements plain Adam only")
            key = (group["lr"], *group["betas"], group["eps"], group["weight_decay"])
            for param in group["params"]:
                if param.grad is not None:
                    batches.setdefault((*key, param.device, param.dtype), []).append((param, _state(optimizer, param)))
    if not batches:
        return
    torch._foreach_add_([state["step"] for batch in batches.values() for _, state in batch], 1)
    for (lr, beta1, beta2, eps, weight_decay, _, _), batch in batches.items():
        params = [param for param, _ in batch]
        torch._fused_adam_(params, [p.grad for p in params], [s["exp_avg"] for _, s in batch],
                           [s["exp_avg_sq"] for _, s in batch], [], [s["step"] for _, s in batch], lr=lr,
                           beta1=beta1, beta2=beta2, weight_decay=weight_decay, eps=eps, amsgrad=False,
                           maximize=False)
        for param in params:
            param.grad = None
