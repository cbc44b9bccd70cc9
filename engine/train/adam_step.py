"""One Adam step for all of a run's optimizers, with a handful of host calls.

Why not `optimizer.step()` for each: a training step has eight Adam optimizers (seven Gaussian parameters,
each its own so gsplat's strategies can move its state when Gaussians are added or relocated, plus the
classifier), and each `Adam.step` spends about 0.2 ms of host time in Python (hooks, grouping, checks):
1.6 ms a step on the H200's host, while the update's GPU work is 0.45 ms (docs/BENCHMARKS.md, "Where a
training step goes"). The host time matters because the loop is bound by it.

The update is torch's own fused Adam kernel (`torch._fused_adam_`, what `Adam(fused=True)` runs), so the
numbers are those of `Adam(fused=True).step()`; parameters with the same hyperparameters share one call,
and every step counter advances in one `_foreach_add_`. The state stays in the optimizers, where gsplat's
strategies and checkpoints find it.
"""

from __future__ import annotations

from collections.abc import Iterable

import torch


def _state(optimizer: torch.optim.Optimizer, param: torch.Tensor) -> dict:
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


def adam_step(optimizers: Iterable[torch.optim.Optimizer]) -> None:
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
