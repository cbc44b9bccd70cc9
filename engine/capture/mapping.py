"""SfM's mapping step for `capture`: the reconstruction that places the most photos, and a reason for each photo
it leaves out.

Why more than one mapper: COLMAP's incremental mapper grows one model from a pair of photos and drops what it
cannot attach, without a word; on phone captures it placed 30 of 44 photos of a clock and 70 of 102 of a plush
toy, where the global mapper (GLOMAP, `pycolmap.global_mapping` in COLMAP 4) placed all of them from the same
matches in seconds. On others the global mapper fails outright (the shared statue capture: no model at all) where
the incremental one places every photo. So `best` (the default) runs the incremental mapper, and only when it
leaves photos out, the incremental mapper with a relaxed first pair (RELAXED) and the global mapper, and keeps the
model that places the most (the earlier one on a tie). On a generated livingroom's 40 photos: incremental 36,
global 40. The global mapper samples: with more than one thread its result differs from run to run even with a
fixed seed (on a 40-frame video of that orbit it placed 40 in five runs of six and 34 in one; 27 and 34 on another
machine, with either seed), so where it too leaves photos out `best` runs it once more with the next seed
(`global-reseeded`), and last (`extended`) the incremental mapper continues the model kept so far, registering
the photos it left out against its points with COLMAP's registration thresholds relaxed (EXTEND): with six
consecutive frames of that video taken out of the global model, COLMAP's thresholds placed two of them back, EXTEND
all six, each within 2% of the scene's size of where the full model had it (once under load one round placed
three: the extension runs again from its own result while it places more, EXTEND_ROUNDS).

A photo left out gets the first reason that holds: it went into a smaller model; it is blurred (the variance of
its Laplacian under BLUR_SHARE of the set's median); it has too few verified matches with any other photo (under
the mapper's minimum); or it matched but no mapper could place it (its best partner named).
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

from engine.capture.photos import sharpness

MAPPERS = ("best", "incremental", "global")
RELAXED = {"init_min_num_inliers": 50, "init_min_tri_angle": 8.0}  # COLMAP's: 100 inliers, 16 degrees
EXTEND = {"abs_pose_min_num_inliers": 15, "abs_pose_min_inlier_ratio": 0.1,  # COLMAP's: 30 inliers, 0.25,
          "max_reg_trials": 10}  # and 3 tries a photo
EXTEND_ROUNDS = 3  # the extension runs again from its own result while it places more
BLUR_SHARE = 0.35  # sharper than this share of the set's median sharpness is not blurred
SHARPNESS_PX = 512  # longer side the sharpness is measured at (so photo size does not decide it)


@dataclass
class Mapped:
    """The model kept, which attempt made it, how many photos each attempt placed, and the photos that went into
    a smaller model of the kept attempt (name -> that model's size)."""

    model: object
    mapper: str
    tried: dict[str, int] = field(default_factory=dict)
    elsewhere: dict[str, int] = field(default_factory=dict)


def map_photos(database: Path, images: Path, work: Path, mapper: str, threads: int, token, progress,
               seed: int = 0) -> Mapped | None:
    """The reconstruction placing the most photos among the attempts `mapper` names (see the module docstring);
    None when cancelled. `progress()` is called per image the incremental mapper registers. `seed` is the
    mappers' sampling seed (COLMAP's default, -1, draws a new one each run)."""
    total = _image_count(database)
    attempts = {"best": ("incremental", "incremental-relaxed", "global", "global-reseeded", "extended"),
                "incremental": ("incremental",), "global": ("global",)}[mapper]
    kept: Mapped | None = None
    for attempt in attempts:
        start = kept.model if kept is not None else None
        if attempt == "extended" and start is None:
            break  # nothing placed to extend
        models = _run(attempt, database, images, work / attempt, threads, token, progress, seed, start)
        if token.is_cancelled:
            return None
        placed = max((m.num_reg_images() for m in models.values()), default=0)
        if kept is None:
            kept = Mapped(None, attempt)
        kept.tried[attempt] = placed
        if models and placed > (kept.model.num_reg_images() if kept.model is not None else 0):
            best = max(models, key=lambda k: models[k].num_reg_images())
            kept.model, kept.mapper = models[best], attempt
            kept.elsewhere = {name: m.num_reg_images() for k, m in models.items() if k != best
                              for name in placed_names(m)}
        if kept.model is not None and kept.model.num_reg_images() == total:
            break  # every photo placed: the other attempts cannot do better
    return kept


def placed_names(model) -> set[str]:
    """The names of the photos a reconstruction registered."""
    return {model.images[i].name for i in model.reg_image_ids()}


def _run(attempt: str, database: Path, images: Path, out: Path, threads: int, token, progress, seed: int,
         start=None) -> dict:
    """The models one attempt makes (id -> reconstruction); `extended` continues `start`, the model kept so far."""
    import pycolmap

    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    if attempt.startswith("global"):  # GLOMAP takes no cancellation token: a stop waits for it to finish
        options = pycolmap.GlobalPipelineOptions()
        options.num_threads, options.random_seed = threads, seed + (attempt == "global-reseeded")
        return pycolmap.global_mapping(database, images, out, options=options)
    if attempt == "extended":
        return extend(start, database, images, out, threads, token, progress, seed)
    options = _incremental(threads, seed, RELAXED if attempt == "incremental-relaxed" else {})
    return pycolmap.incremental_mapping(database, images, out, options=options, next_image_callback=progress,
                                        cancellation_token=token)


def extend(model, database: Path, images: Path, out: Path, threads: int, token, progress, seed: int = 0) -> dict:
    """The incremental mapper continuing `model` with registration relaxed (EXTEND): the photos of `database` it
    left out, registered against its points (id -> reconstruction). Again from its own result, up to EXTEND_ROUNDS
    times, while a round places more: a photo placed late adds the points its neighbours need. Round k reads its
    start from OUT/startK and writes to OUT/roundK."""
    import pycolmap

    models: dict = {0: model}
    for round_ in range(EXTEND_ROUNDS):
        start, result = out / f"start{round_}", out / f"round{round_}"
        start.mkdir(parents=True)
        result.mkdir()
        largest = max(models.values(), key=lambda m: m.num_reg_images())
        largest.write_binary(str(start))
        grown = pycolmap.incremental_mapping(database, images, result,
                                             options=_incremental(threads, seed, EXTEND), input_path=start,
                                             next_image_callback=progress, cancellation_token=token)
        if not grown or token is not None and token.is_cancelled:
            break
        models = grown
        if max(m.num_reg_images() for m in grown.values()) <= largest.num_reg_images():
            break
    return models


def _incremental(threads: int, seed: int, mapper: dict):
    """The incremental mapper's options: COLMAP's, with `mapper`'s values in place of its own."""
    import pycolmap

    options = pycolmap.IncrementalPipelineOptions()
    options.num_threads, options.random_seed = threads, seed
    for name, value in mapper.items():
        setattr(options.mapper, name, value)
    return options


def _image_count(database: Path) -> int:
    import pycolmap

    db = pycolmap.Database.open(database)
    try:
        return db.num_images()
    finally:
        db.close()


def best_matches(database: Path) -> dict[str, tuple[int, str]]:
    """Each photo's largest number of verified (inlier) matches with another photo, and that photo's name."""
    import pycolmap

    db = pycolmap.Database.open(database)
    try:
        names = {image.image_id: image.name for image in db.read_all_images()}
        pair_ids, geometries = db.read_two_view_geometries()
    finally:
        db.close()
    best = {name: (0, "") for name in names.values()}
    for pair_id, geometry in zip(pair_ids, geometries, strict=True):
        a, b = (names[i] for i in pycolmap.pair_id_to_image_pair(pair_id))
        count = len(geometry.inlier_matches)
        if count > best[a][0]:
            best[a] = (count, b)
        if count > best[b][0]:
            best[b] = (count, a)
    return best


def photo_sharpness(path: Path) -> float:
    """engine.capture.photos.sharpness of the photo's grey image at SHARPNESS_PX on its longer side."""
    grey = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if grey is None:
        return 0.0
    scale = SHARPNESS_PX / max(grey.shape)
    if scale < 1:
        grey = cv2.resize(grey, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
    return sharpness(grey)


def unplaced_reasons(mapped: Mapped, database: Path, images: Path, names: list[str],
                     min_matches: int = 15) -> dict[str, str]:
    """Why each photo of `names` that the kept model did not place was left out (see the module docstring)."""
    placed = placed_names(mapped.model)
    left = [name for name in names if name not in placed]
    if not left:
        return {}
    matches = best_matches(database)
    sharp = {name: photo_sharpness(images / name) for name in names}
    median = float(np.median(list(sharp.values())))
    reasons = {}
    for name in left:
        count, partner = matches.get(name, (0, ""))
        if name in mapped.elsewhere:
            reasons[name] = f"placed in another model of {mapped.elsewhere[name]} photos, apart from the kept one"
        elif (value := sharp[name]) < BLUR_SHARE * median:
            reasons[name] = f"blurred (sharpness {value:.0f}, {value / max(median, 1e-9):.0%} of the set's median)"
        elif count < min_matches:
            reasons[name] = f"too few matches with any other photo ({count} verified, {min_matches} needed)"
        else:
            reasons[name] = f"matched ({count} verified with {partner}) but no mapper could place it"
    return reasons
