"""How well objects found without ground truth (engine.segment.run) match a generated scene's exact
instance masks, and the user-mask case it must survive: ids that disagree across views, segments split or
merged. Used by the tests and benchmarks/segments.py.
"""

from __future__ import annotations

import numpy as np


def iou(a: np.ndarray, b: np.ndarray) -> float:
    union = (a | b).sum()
    return float((a & b).sum() / union) if union else 0.0


def proposal_scores(found: list[np.ndarray], truth: list[np.ndarray], truth_ids: list[int]) -> dict:
    """Per ground-truth object, the found object that matches it best over these views (IoU of the pixels
    pooled over views) and that IoU; found objects that hold at least half of two ground-truth objects
    (merges)."""
    found_flat, truth_flat = np.concatenate([f.ravel() for f in found]), np.concatenate([t.ravel() for t in truth])
    best = {}
    for g in truth_ids:
        in_g = truth_flat == g
        candidates = np.unique(found_flat[in_g])
        scores = {int(k): iou(found_flat == k, in_g) for k in candidates if k != 0}
        k = max(scores, key=scores.get, default=0)
        best[int(g)] = {"found": k, "iou": round(scores.get(k, 0.0), 4)}
    merges = 0
    for k in np.unique(found_flat):
        if k == 0:
            continue
        held = [g for g in truth_ids if (truth_flat == g).any()
                and ((found_flat == k) & (truth_flat == g)).sum() >= 0.5 * (truth_flat == g).sum()]
        merges += len(held) >= 2
    return {"objects": best, "merges": merges}


def perturb_masks(masks: list[np.ndarray], rng: np.random.Generator, share: float = 0.1
                  ) -> tuple[list[np.ndarray], list[dict[int, int]]]:
    """Instance masks as a 2D tool gives them: ids permuted per view, and `share` of the segments either
    split in two (a straight cut through their centre) or merged with another segment of the view. Returns
    the masks and, per view, each new id's ground-truth object (the majority of its pixels)."""
    out, owners = [], []
    for mask in masks:
        ids = [int(i) for i in np.unique(mask) if i != 0]
        table = np.zeros(256, np.int64)
        table[ids] = rng.permutation(np.arange(1, len(ids) + 1))
        new = table[mask]
        free = len(ids) + 1
        for g in ids:
            if rng.random() >= share:
                continue
            pixels = new == table[g]
            if rng.random() < 0.5 and len(ids) > 1:  # merge with another segment of this view
                other = table[rng.choice([i for i in ids if i != g])]
                new[pixels] = other
            else:  # split along a random direction through the centre
                rows, cols = np.nonzero(pixels)
                angle = rng.uniform(0, np.pi)
                side = (cols - cols.mean()) * np.cos(angle) + (rows - rows.mean()) * np.sin(angle) > 0
                new[rows[side], cols[side]] = free
                free += 1
        out.append(new.astype(np.uint8))
        owners.append({int(k): int(np.bincount(mask[new == k]).argmax()) for k in np.unique(new) if k != 0})
    return out, owners


def association_accuracy(given: list[np.ndarray], owners: list[dict[int, int]], found: list[np.ndarray]) -> float:
    """Share of the given segments whose pixels mostly landed in the object found for their ground-truth
    object (that object: the one overlapping it most over all views)."""
    pairs: dict[tuple[int, int], int] = {}
    votes = []
    for mask, owner, result in zip(given, owners, found, strict=True):
        for k, g in owner.items():
            values, counts = np.unique(result[mask == k], return_counts=True)
            for v, c in zip(values, counts, strict=True):
                pairs[(g, int(v))] = pairs.get((g, int(v)), 0) + int(c)
            votes.append((g, int(values[counts.argmax()])))
    best: dict[int, tuple[int, int]] = {}
    for (g, v), c in pairs.items():
        if v != 0 and c > best.get(g, (0, 0))[1]:
            best[g] = (v, c)
    match = {g: v for g, (v, _) in best.items()}
    return float(np.mean([match.get(g) == v for g, v in votes])) if votes else 0.0
