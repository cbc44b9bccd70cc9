"""k nearest neighbours by chunked exact search: no extra dependency, bounded memory on CPU and GPU."""

from __future__ import annotations

import torch


def knn(queries: torch.Tensor, points: torch.Tensor, k: int, exclude_self: bool = False,
        chunk: int = 1024) -> tuple[torch.Tensor, torch.Tensor]:
    """Distances and indices (Q, k) of the k nearest `points` (N, 3) to each of `queries` (Q, 3).

    With `exclude_self`, queries are assumed to be among the points and their zero-distance self match is
    dropped (k + 1 are searched).
    """
    extra = 1 if exclude_self else 0
    k_eff = min(k + extra, len(points))
    dists, ids = [], []
    for start in range(0, len(queries), chunk):
        d = torch.cdist(queries[start:start + chunk], points)
        top = torch.topk(d, k_eff, dim=1, largest=False)
        dists.append(top.values[:, extra:])
        ids.append(top.indices[:, extra:])
    return torch.cat(dists), torch.cat(ids)


def knn_distances(points: torch.Tensor, k: int) -> torch.Tensor:
    """(N, k) distances from each point to its k nearest other points."""
    return knn(points, points, k, exclude_self=True)[0]
