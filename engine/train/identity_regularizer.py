"""Gaussian Grouping's 3D identity regulariser, with cached neighbour lists.

Loss: for sampled Gaussians q, mean over q and its k nearest neighbours n of KL(p_q || p_n), where p is
the softmax of the classifier applied to the identity encoding; divided by the class count, times lambda.
The reference searches all Gaussians every time (cdist from 1000 samples to up to 300k points, its
memory complaint); here a pool of queries and their neighbours is kept and refreshed only when the
Gaussians were densified or every `refresh_every` steps, so a regulariser step is a gather.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import torch

from engine.base.knn import knn


@dataclass
class IdentityRegularizer:
    k: int = 5
    samples: int = 1000
    weight: float = 2.0
    pool_size: int = 8192
    refresh_every: int = 500
    pool: torch.Tensor | None = field(default=None, repr=False)  # (P,) query indices
    neighbours: torch.Tensor | None = field(default=None, repr=False)  # (P, k)
    refreshed_at: int = -1
    source: weakref.ref | None = field(default=None, repr=False)  # the means the lists were built from

    def refresh(self, means: torch.Tensor, step: int, generator: torch.Generator) -> None:
        n = len(means)
        self.pool = torch.randperm(n, generator=generator)[: self.pool_size].to(means.device)
        chunk = max(1, int(2e8 // max(n, 1)))  # bounds the cdist block to about 800 MB
        self.neighbours = knn(means.detach()[self.pool], means.detach(), self.k, exclude_self=True, chunk=chunk)[1]
        self.refreshed_at, self.source = step, weakref.ref(means)

    def stale(self, means: torch.Tensor, step: int) -> bool:
        """gsplat's strategies replace the means Parameter whenever they add, remove or move Gaussians."""
        return self.source is None or self.source() is not means or step - self.refreshed_at >= self.refresh_every

    def loss(self, identity: torch.Tensor, classifier: torch.nn.Module, means: torch.Tensor, step: int,
             generator: torch.Generator) -> torch.Tensor:
        if self.stale(means, step):
            self.refresh(means, step, generator)
        if self.neighbours.shape[1] == 0:  # a single Gaussian (a completion's tiny hole) has no neighbour to agree
            return identity.sum() * 0.0  # with; a mean over none would be NaN and spoil every parameter
        pick = torch.randint(len(self.pool), (min(self.samples, len(self.pool)),), generator=generator)
        pick = pick.to(means.device)
        queries, neighbours = self.pool[pick], self.neighbours[pick]
        log_q = torch.log_softmax(classifier(identity[queries]), dim=-1)  # (S, C)
        log_n = torch.log_softmax(classifier(identity[neighbours]), dim=-1)  # (S, k, C)
        kl = (log_q.exp()[:, None] * (log_q[:, None] - log_n)).sum(-1)
        return self.weight * kl.mean() / log_q.shape[-1]

    def state_dict(self) -> dict:
        return {"pool": self.pool, "neighbours": self.neighbours, "refreshed_at": self.refreshed_at}

    def load_state_dict(self, state: dict, means: torch.Tensor) -> None:
        if state["pool"] is None:
            return
        self.pool, self.neighbours = state["pool"].to(means.device), state["neighbours"].to(means.device)
        self.refreshed_at, self.source = state["refreshed_at"], weakref.ref(means)
