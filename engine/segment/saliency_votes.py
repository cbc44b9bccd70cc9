"""The object a capture is about, from salient-object evidence voted across views (`segment --auto`).

Each training view's photo gets a salient-object map (engine.segment.salient); every Gaussian on the surface a
view shows (its centre within `rel_tol` of the view's rendered depth) takes that map's value under it. Its vote
is the mean over the views that see it: a subject is salient from nearly every side, while a wallpaper rose
taken for it in a few views, or the background behind the subject, is salient in few of the views that see it,
so one view's wrong mask is outvoted. Gaussians no view sees at the surface (inside an object) take the
vote of the nearest one seen.

The geometry and the votes must agree before an object is named the subject (`subject`): it is the largest
connected piece of the Gaussians that vote salient and that the geometry leaves free of every support (off the
floor, table and wall planes, within the cameras' orbit), less a pedestal it stands on. The geometry's own
proposals split at thin parts (a statue's ankles) and cannot tell the object a capture is about; the votes
alone take in the wallpaper behind a wall-mounted object.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
import torch

from engine.base.knn import knn
from engine.base.progress import Progress
from engine.formats.cameras import Camera, project, sample_nearest
from engine.geometry.scene_geometry import ProposalConfig, voxel_codes, voxel_components
from engine.segment.proposals import merge_stacked

MAX_VIEWS = 24  # views voting: evenly spread over the training views (u2netp: about 0.1-0.5 s a view on a CPU)
PEDESTAL_FOOTPRINT = 3.0  # a pedestal's footprint is at least this many times its subject's
PEDESTAL_COLOUR = 0.3  # ... and its mean colour at least this far from the subject's (RGB in [0, 1])
PEDESTAL_CONFIRM = 2.5  # ... and, with the faint Gaussians the growth reaches, still this many times: a toy's tracks
# 1.8 (tabletop_s5, 3.5 on its opaque Gaussians alone); the statue capture's boulder 4.6 on its opaque ones
STEP = 1.0  # voxels a growth step reaches: a salient picture hung 1.7 voxels beside a plaque stays out
GROW = 30  # growth steps at most: 0.6 R where the voxel is 0.02 R (300,000 Gaussians), what six steps of the
# Gaussians' spacing reached on the tiny runs the rule was tuned on (0.097 R on the CPU wallmount)
GROW_VOTE = 0.2  # the share of views a Gaussian needs salient for the subject to grow over it: a plaque's wood votes
# 0.1-0.4 where its head votes 0.8 and more (wallmount_s5, 300,000 Gaussians: target IoU 0.47 growing over 0.5 only,
# 0.79 over 0.2, the picture beside it none of it either way)
BASE_DEPTH = 2.0  # voxels under a pedestal's cut that the growth may reach over Gaussians of the subject's colour:
# the plate a figure stands on lies in the pedestal's top slice (statue capture at 728921d: its bronze base stayed
# on the boulder as a dark patch); a plaque lower down the pedestal's side stays


@dataclass
class VoteConfig:
    salient: bool = True  # --auto: rank objects by salient-object votes (u2netp weights from the set-up)
    salient_weights: str = ""  # u2netp.onnx (default SALIENT_WEIGHTS or the set-up's .weights/)
    min_vote: float = 0.5  # a subject's Gaussians are salient in at least this share of the views seeing them
    grow_vote: float = GROW_VOTE  # those it grows over (off the level supports): salient in this share of views


def salient_votes(means: np.ndarray, cameras: list[Camera], images: list[np.ndarray], depths: list[np.ndarray],
                  net, rel_tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Per Gaussian, its mean salience over the views that see it at the surface (nearest seen one's where
    none does), and how many views saw it."""
    total, count = np.zeros(len(means)), np.zeros(len(means), np.int64)
    progress = Progress("segment: salient votes", len(cameras))
    for k, (camera, image, depth) in enumerate(zip(cameras, images, depths, strict=True)):
        probability = net.probability(image)
        u, v, z = project(camera, means)
        surface, inside = sample_nearest(depth, u, v)
        seen = inside & (z > 0) & (np.abs(z - surface) <= rel_tol * np.abs(z))
        value, _ = sample_nearest(probability, u, v)
        total[seen] += value[seen]
        count[seen] += 1
        progress.update(k + 1)
    progress.close()
    votes = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    unseen, seen = np.flatnonzero(count == 0), np.flatnonzero(count > 0)
    if len(unseen) and len(seen):
        nearest = knn(torch.as_tensor(means[unseen]), torch.as_tensor(means[seen]), 1)[1][:, 0].numpy()
        votes[unseen] = votes[seen][nearest]
    return np.nan_to_num(votes), count


def voting_views(train: list[int]) -> list[int]:
    """At most MAX_VIEWS training views, evenly spread."""
    if len(train) <= MAX_VIEWS:
        return list(train)
    return [train[k] for k in np.linspace(0, len(train) - 1, MAX_VIEWS).round().astype(int)]


def subject(votes: np.ndarray, means: np.ndarray, colours: np.ndarray, solid: np.ndarray, free: np.ndarray,
            near: np.ndarray, up: np.ndarray, voxel: float, min_vote: float,
            stack_gap: float = ProposalConfig.stack_gap, grow_vote: float = GROW_VOTE,
            level: np.ndarray | None = None) -> tuple[np.ndarray, dict]:
    """(N,) bool: the Gaussians of the object the capture is about, and what was found. The salient Gaussians the
    geometry leaves free (off every support plane, engine.segment.proposals.find_supports), their largest connected
    piece (pieces stacked on one another within `stack_gap` voxels joined, as the proposals join them: one statue
    capture's figure came apart at the waist, and its legs went with the boulder while the upper body stayed) less a
    pedestal it stands on (the lowest of `pedestal_cuts` on the piece where the whole piece the growth reaches, faint
    Gaussians too, is still PEDESTAL_CONFIRM times wider below the cut than above: tabletop_s5's toy body held few
    opaque Gaussians above its opaque tracks, whose footprint passed three times the body's (3.5), and the tracks
    were cut off, IoU 0.47 against 0.87; with the body's faint Gaussians 1.8), then grown in steps of `STEP` voxels
    over the salient Gaussians touching it, faint ones and those within a wall's band too (`grow`, at most `GROW`
    steps): a plaque mounted flat on a wall lies in the wall's band. Never into the `level` supports' bands (a
    floor's, a table's): a salient sheet or mat the object stands on went with it (the tiny tabletop run: 458 of the
    mat's Gaussians for 84 of the toy's, IoU 0.13 against 0.43 without), and the ground at a figure's foot did (tiny
    statue 0.48 against 0.58); the object's own foot within the band (3% of the tiny statue's) is left to `remove`'s
    hull. The growth needs less of the votes than the piece it starts from (`grow_vote`, as a hysteresis threshold
    does): the salient maps light a mounted head far more than the plaque behind it, and the bare wall around both
    hardly at all. A picture on the same wall votes as salient as the plaque; the wall between them does not, and a
    step no longer than a voxel does not cross it. Under a pedestal's cut the growth reaches `BASE_DEPTH` voxels,
    over Gaussians nearer the subject's colour than the pedestal's only: the cut is a whole voxel slice, and a base
    plate thinner than one shares the pedestal's top slice. It also reaches down to the pedestal's top under the
    subject's feet, while those slices have the subject's colour more than the pedestal top's (`_standing_under`: a
    base taller than that, of a colour between the two)."""
    chosen = np.zeros(len(means), bool)
    salient = np.flatnonzero(free & solid & (votes >= min_vote))
    if len(salient) == 0:
        return chosen, {"subject": None}
    voxel_of, label = voxel_components(means[salient], voxel)
    part = merge_stacked(means[salient], voxel_of, label, up, stack_gap * voxel)[voxel_of]
    members = salient[part == np.bincount(part).argmax()]
    rest = near & (votes >= min(grow_vote, min_vote))
    if level is not None:
        rest &= ~level
    cut = _confirmed_cut(means, colours, members, rest, up, voxel)
    if cut is not None:
        height = means @ up
        upper = height[members] >= cut
        base = _subject_coloured(colours, colours[members[upper]].mean(0), colours[members[~upper]].mean(0))
        under = _standing_under(means, height, colours, members, up, voxel, cut)
        rest &= (height >= cut) | (base & (height >= cut - BASE_DEPTH * voxel)) | under
        members = members[upper]
    chosen = grow(means, members, rest, STEP * voxel, GROW)
    return chosen, {"subject": "votes", "vote": round(float(votes[chosen].mean()), 3),
                    "salient_pieces": int(len(np.unique(part))), "pedestal": cut is not None}


def _confirmed_cut(means: np.ndarray, colours: np.ndarray, members: np.ndarray, rest: np.ndarray, up: np.ndarray,
                   voxel: float) -> float | None:
    """The lowest of the opaque piece's `pedestal_cuts` at which the whole piece the growth reaches (faint Gaussians
    too) is still PEDESTAL_CONFIRM times wider below than above, or None; the growth only where a cut is tried."""
    whole = None
    for cut in pedestal_cuts(means[members], colours[members], up, voxel):
        if whole is None:
            whole = means[grow(means, members, rest, STEP * voxel, GROW)]
        if footprint_ratio(whole, up, voxel, cut) >= PEDESTAL_CONFIRM:
            return cut
    return None


def _standing_under(means: np.ndarray, height: np.ndarray, colours: np.ndarray, members: np.ndarray, up: np.ndarray,
                    voxel: float, cut: float) -> np.ndarray:
    """(N,) bool: the base a figure stands on, under the cut. Slice by slice down to the pedestal's top
    (`pedestal_top`), the Gaussians under the subject's feet (`_under_feet`), as long as a slice's opaque ones (the
    piece's `members`) are together nearer the subject's mean colour than the pedestal top's.

    Why: the statue capture at 274f783 cut three slices above the boulder's top (the slices under the cut passed on
    footprint, 3.6-7.2 times, not on colour, 0.25-0.30), and the colour rule's two slices, each Gaussian against the
    whole boulder's mean, took half the bronze base, whose patina lies between the figure's colour and the boulder's:
    the rest stayed on the boulder as a green ghost. A pedestal's own rounded top under the feet has its colour, and
    stays. `height`: `means` along `up`."""
    top = pedestal_top(means[members], up, voxel, cut)
    shoulder = members[(height[members] < top) & (height[members] >= top - BASE_DEPTH * voxel)]
    band = _under_feet(means, height, members, up, voxel, cut, top)
    under = np.zeros(len(means), bool)
    if not len(band) or not len(shoulder):
        return under
    subject_mean, pedestal_mean = colours[members[height[members] >= cut]].mean(0), colours[shoulder].mean(0)
    slice_of = np.floor((cut - height[band]) / voxel).astype(np.int64)
    for k in range(int(slice_of.max()) + 1):
        here = band[slice_of == k]
        opaque = here[np.isin(here, members)]  # the faint ones' colours say little (statue: 0.47 against 0.33)
        if len(opaque) and not _subject_coloured(colours[opaque].mean(0, keepdims=True), subject_mean,
                                                 pedestal_mean)[0]:
            break
        under[here] = True
    return under


def _under_feet(means: np.ndarray, height: np.ndarray, members: np.ndarray, up: np.ndarray, voxel: float,
                cut: float, top: float) -> np.ndarray:
    """Indices of the Gaussians between the heights `top` and `cut` that stand in the voxel columns of the piece's
    lowest BASE_DEPTH slices above the cut, or one column beside them."""
    feet = members[(height[members] >= cut) & (height[members] < cut + BASE_DEPTH * voxel)]
    band = np.flatnonzero((height >= top) & (height < cut))
    if not len(band) or not len(feet):
        return band[:0]
    feet_columns = voxel_columns(means[feet], up, voxel)
    beside = np.concatenate([feet_columns + (dx, dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)])
    return band[np.isin(_column_codes(voxel_columns(means[band], up, voxel)), _column_codes(beside))]


def _column_codes(columns: np.ndarray) -> np.ndarray:
    """One integer a voxel column (N, 2), by the voxels' own codes (`voxel_codes`) at height 0."""
    return voxel_codes(np.c_[columns, np.zeros(len(columns), columns.dtype)])


def pedestal_top(points: np.ndarray, up: np.ndarray, voxel: float, cut: float) -> float:
    """The lowest height, in whole voxels under `cut`, from which every cut up to `cut` passes the footprint test
    (PEDESTAL_FOOTPRINT): where the pedestal's wide top ends and what stands on it begins."""
    height, columns = points @ up, voxel_columns(points, up, voxel)
    floor, lowest = cut, float(height.min()) + 2 * voxel
    while floor - voxel >= lowest - 1e-9 and _column_ratio(columns, height < floor - voxel) >= PEDESTAL_FOOTPRINT:
        floor -= voxel
    return floor


def grow(means: np.ndarray, seeds: np.ndarray, allowed: np.ndarray, reach: float, steps: int) -> np.ndarray:
    """(N,) bool: `seeds` (indices) and the `allowed` points joined to them by at most `steps` steps of `reach`.

    Why more than the six steps of one voxel before: six voxels were six times the Gaussians' spacing on a tiny run
    (0.58 R on the CPU wallmount: the plaque and horns taken, IoU 0.87) but 0.12 R at 300,000 Gaussians, where the
    voxel is 0.02 R (about 11 cm on wallmount_s5, less than the plaque's half height: the head alone, IoU 0.47 at
    f1affc9). Each step measures the points left only against those the last step added; what an earlier one added
    was measured already."""
    chosen = np.zeros(len(means), bool)
    chosen[seeds] = True
    frontier, todo = seeds, np.flatnonzero(allowed & ~chosen)
    for _ in range(steps):
        if not len(frontier) or not len(todo):
            break
        reached = knn(torch.as_tensor(means[todo]), torch.as_tensor(means[frontier]), 1)[0][:, 0].numpy() <= reach
        frontier, todo = todo[reached], todo[~reached]
        chosen[frontier] = True
    return chosen


def _subject_coloured(colours: np.ndarray, subject_mean: np.ndarray, pedestal_mean: np.ndarray) -> np.ndarray:
    """(N,) bool: the colours nearer the subject's mean than its pedestal's (pedestal_cuts sets them apart by at least
    PEDESTAL_COLOUR)."""
    return np.linalg.norm(colours - subject_mean, axis=1) < np.linalg.norm(colours - pedestal_mean, axis=1)


def pedestal_cuts(points: np.ndarray, colours: np.ndarray, up: np.ndarray, voxel: float) -> Iterator[float]:
    """The heights where a salient piece's subject may stand on a pedestal that is salient with it (a statue on
    its boulder, voted one piece since every photo of the statue frames the boulder too), lowest first. Tried
    from the bottom in slices of one voxel: each cut below which the piece's footprint (its occupied voxel
    columns) is at least PEDESTAL_FOOTPRINT times that above, whose two sides differ in mean colour by at least
    PEDESTAL_COLOUR, with the lower side at most half the piece's height. Measured on the shared statue
    capture: the boulder's cut has footprints 181 / 39 columns (4.6) and colours 0.45 apart at a fifth of the
    height; the skull's stem under its skull never passes 1.7 (so it stays with the skull). A toy's tracks are
    as wide as its body above them, and stay. All of them, not the lowest alone: `subject` confirms each on the
    grown piece, and the lowest may lie on the pedestal's rounded shoulder (the statue capture at e41a552: the
    slice under the boulder's top passed at 3.5, its grown piece at 2.4; the next slice up 5.8, grown 4.4)."""
    height, columns = points @ up, voxel_columns(points, up, voxel)
    level = np.floor((height - height.min()) / voxel).astype(np.int64)
    top = int(level.max())
    for cut in range(2, top // 2 + 1):
        below = level < cut
        contrast = float(np.linalg.norm(colours[below].mean(0) - colours[~below].mean(0)))
        if _column_ratio(columns, below) >= PEDESTAL_FOOTPRINT and contrast >= PEDESTAL_COLOUR:
            yield float(height.min() + cut * voxel)


def voxel_columns(points: np.ndarray, up: np.ndarray, voxel: float) -> np.ndarray:
    """(N, 2) int: each point's column of voxels standing along `up`."""
    basis = np.linalg.svd(np.eye(3) - np.outer(up, up))[0][:, :2]
    return np.floor(points @ basis / voxel).astype(np.int64)


def footprint_ratio(points: np.ndarray, up: np.ndarray, voxel: float, cut: float) -> float:
    """How many times more voxel columns `points` occupy below the height `cut` than above it."""
    return _column_ratio(voxel_columns(points, up, voxel), points @ up < cut)


def _column_ratio(columns: np.ndarray, below: np.ndarray) -> float:
    """How many times more distinct `columns` (N, 2) the points `below` occupy than the rest (at least one)."""
    return len(np.unique(columns[below], axis=0)) / max(len(np.unique(columns[~below], axis=0)), 1)


SHARE_RANGE = (0.02, 0.5)  # a subject outside this share of the scene's Gaussians is worth a second look
MIN_SOLID_SHARE = 0.05  # below this share of solid Gaussians the model may not fit its photos (skull capture:
# 1.4%, median opacity 0, test PSNR 14.5 dB; the statue capture 38%, tiny CPU trainings of the tuning scenes 31-52%)
FIT_PSNR = 18.0  # ...unless its test PSNR says it does: MCMC at a budget larger than a scene needs keeps most of
# it faint (livingroom_s5 at 320x240 and 300k on an H200, 1a0ca30: 2.1% solid at 39.63 dB, its subject found at IoU
# 0.95); real captures' test PSNR 17.0-21.2 (docs/BENCHMARKS.md, "Real captures"), the broken skull's 14.5


def weak_evidence(stats: dict) -> list[str]:
    """Why object_1, the subject `segment --auto` found (its report `stats`), may not be what the photos are
    about; empty when nothing says so. Why: on real captures the subject came out as a patch of a plush toy's
    back (3,853 of 300,000 Gaussians, about 1%) and as a skull with most of its room (78%), both without a word;
    a user should look at the segments sheet before removing it, and knows the click that fixes it. A model
    that is mostly transparent (`solid_share`) and renders its test views badly (`test_psnr`, where the run has
    test views) gives no object to trust, whatever was found in it."""
    fits = (stats.get("test_psnr") or 0.0) >= FIT_PSNR
    if stats.get("solid_share", 1.0) < MIN_SOLID_SHARE and not fits:
        return [f"only {stats['solid_share']:.1%} of the scene's Gaussians are opaque enough to shape it: the "
                "training did not fit the photos (see the run's test PSNR in metrics.json), so no object found in "
                "it can be trusted"]
    if stats.get("subject") is None:
        return ["no salient object stands free of the supports: object_1 is the geometry's first proposal"]
    share, (low, high) = stats.get("subject_share", 0.0), SHARE_RANGE
    if share < low:
        return [f"object_1 holds {share:.1%} of the scene's Gaussians: it may be a part of the subject"]
    if share > high:
        return [f"object_1 holds {share:.0%} of the scene's Gaussians: part of the scene around it may have gone "
                "with it"]
    return []
