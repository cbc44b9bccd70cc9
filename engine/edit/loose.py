"""Loose Gaussians the removed object leaves where it was: what the object selection missed (a segment's frayed
edge, the back of a subject where it met the wall, floaters the training hung in front of it) and that no longer
joins anything. After removal they float in the hole, blurred grey blobs in every view.

A piece of the remaining Gaussians (connected on a voxel grid, engine.segment.proposals.voxel_components) is loose
when every one of its Gaussians lies within `reach` of the object's core: the floor, the wall or the table the
object stood on runs on past that reach and stays, as does anything connected to them. Only Gaussians off every
support plane go (`free`, engine.segment.proposals.find_supports): on a tiny run the wall behind a plaque came
apart into fragments once the plaque went, and taking them cost 0.6 dB. Gaussians of other objects the scene
knows stay whatever their piece.
"""

from __future__ import annotations

import numpy as np
import torch

from engine.base.knn import knn
from engine.geometry.scene_geometry import spacing, voxel_components

REACH = 0.25  # x the core's diagonal: how far from the object a loose piece may lie (and the context twice that)


def loose_pieces(means: np.ndarray, removed: np.ndarray, free: np.ndarray, core: np.ndarray,
                 voxel: float) -> np.ndarray:
    """(N,) bool: the remaining Gaussians (not `removed`), `free` of supports and of other objects, in pieces
    that lie wholly within REACH of the object's `core` (M, 3), connected through voxels of at least `voxel`."""
    loose = np.zeros(len(means), bool)
    if len(core) < 20:
        return loose
    reach = REACH * float(np.linalg.norm(core.max(axis=0) - core.min(axis=0)))
    pool = np.flatnonzero(~removed)
    distance = knn(torch.as_tensor(means[pool]), torch.as_tensor(core), 1)[0][:, 0].numpy()
    near = distance <= 2 * reach
    pool, distance = pool[near], distance[near]
    if len(pool) == 0:
        return loose
    voxel_of, label = voxel_components(means[pool], max(voxel, spacing(means[pool])))
    part = label[voxel_of]
    reaching = np.unique(part[distance > reach])
    loose[pool[~np.isin(part, reaching) & free[pool]]] = True
    return loose
