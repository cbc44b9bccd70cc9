"""Objects for a run without ground-truth masks (engine.segment.run): from a user's masks whose ids do
not agree across views, or from a 3D box; afterwards `remove --object` works as on a generated scene."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import torch

from engine.base.errors import InputError
from engine.edit.removal import RemovalConfig, run_removal
from engine.formats.cameras import Camera
from engine.geometry.planes import level_normal, support_planes
from engine.geometry.scene_geometry import Frame, components, find_supports, strip_of_walls, voxel_components
from engine.io.image_io import read_png, write_png
from engine.metrics.segment_scores import association_accuracy, iou, perturb_masks, proposal_scores
from engine.segment.proposals import split_pieces
from engine.segment.run import (
    SegmentConfig,
    lift_masks,
    pieces_under,
    rendered_under,
    renders_at,
    renumber,
    run_segment,
    subject_supports,
)
from engine.segment.saliency_votes import subject, weak_evidence
from engine.train.trained_run import load_run, load_run_scene
from tests.conftest import setup_weight
from tests.gaussian_grids import gaussians


@pytest.fixture
def run_copy(tiny_run: Path, tmp_path: Path) -> Path:
    """The shared tiny run, copied: segmenting writes RUN/segments/, which changes how the run loads."""
    copy = tmp_path / "run"
    shutil.copytree(tiny_run, copy, ignore=shutil.ignore_patterns("checkpoints", "removed", "holes", "inpainted"))
    return copy


def shuffled_masks(run: Path, out: Path, seed: int = 0) -> dict[int, int]:
    """The scene's instance masks of the training views with the ids permuted per view (as SAM gives them);
    returns the target's id."""
    scene = load_run_scene(run)
    rng = np.random.default_rng(seed)
    for i in scene.train:
        table = np.concatenate([[0], rng.permutation(np.arange(1, 256))]).astype(np.uint8)
        write_png(out / Path(scene.cameras[i].name).with_suffix(".png"), table[scene.masks[i]])
    return scene.target.id


def test_masks_with_ids_shuffled_per_view_give_objects_that_remove_works_on(run_copy: Path, tmp_path: Path):
    scene = load_run_scene(run_copy)
    target = shuffled_masks(run_copy, tmp_path / "masks")
    # at the default floor of 20 Gaussians (the tiny run's small objects hold 9-25 each, so some fall below it):
    # the target must still be found, as a user's run would have it
    report = run_segment(load_run(run_copy), SegmentConfig(run=str(run_copy), from_masks=str(tmp_path / "masks"),
                                                           device="cpu"))
    assert report["objects"] >= 2 and report["joined"] >= 0.7 * report["segments"]
    segmented = load_run_scene(run_copy)  # the run now loads with the segments' objects and masks
    objects = {o.name: o.id for o in segmented.objects}
    # the object that covers the target best, on the views that never gave a mask (the test views)
    best = max(objects.values(), key=lambda k: np.mean([iou(segmented.masks[i] == k, scene.masks[i] == target)
                                                         for i in scene.test]))
    score = np.mean([iou(segmented.masks[i] == best, scene.masks[i] == target) for i in scene.test])
    assert score >= 0.5, f"target IoU on test views {score:.2f}"
    name = next(n for n, k in objects.items() if k == best)
    removal = run_removal(RemovalConfig(run=str(run_copy), object=name, out=str(tmp_path / "removed"), device="cpu"))
    assert removal["removed"] > 0 and json.loads((tmp_path / "removed" / "removal.json").read_text())["object"]


def test_a_box_and_selected_indices_add_named_objects(run_copy: Path, tmp_path: Path):
    """Blender's Object from Selection: a box, then selected proxy points, each one more object."""
    means = load_run(run_copy).gaussians["means"].numpy()
    lo, hi = np.percentile(means, 45, axis=0), np.percentile(means, 55, axis=0)
    run_segment(load_run(run_copy), SegmentConfig(run=str(run_copy), box=[*lo, *hi], name="thing", device="cpu"))
    picked = np.arange(0, len(means), 7)
    np.savetxt(tmp_path / "picked.txt", picked, fmt="%d")
    run_segment(load_run(run_copy), SegmentConfig(run=str(run_copy), indices=str(tmp_path / "picked.txt"),
                                                  device="cpu"))
    run = load_run(run_copy)
    assert [o.name for o in run.scene.objects] == ["thing", "object_2"]
    inside = np.all((means >= lo) & (means <= hi), axis=1)
    inside[picked] = False  # the later selection took these
    removal = run_removal(RemovalConfig(run=str(run_copy), object="thing", hull=False, out=str(tmp_path / "r"),
                                        device="cpu"))
    assert removal["removed"] == inside.sum()
    with pytest.raises(InputError, match="already has an object named 'thing'"):
        run_segment(run, SegmentConfig(run=str(run_copy), box=[*lo, *hi], name="thing", device="cpu"))
    np.savetxt(tmp_path / "bad.txt", [len(means)], fmt="%d")
    with pytest.raises(InputError, match="indices between 0 and"):
        run_segment(run, SegmentConfig(run=str(run_copy), indices=str(tmp_path / "bad.txt"), device="cpu"))
    # the objects before the last selection were kept: --restore brings them back, and again swaps forward
    run_segment(run, SegmentConfig(run=str(run_copy), restore=True))
    assert [o.name for o in load_run(run_copy).scene.objects] == ["thing"]
    run_segment(run, SegmentConfig(run=str(run_copy), restore=True))
    assert [o.name for o in load_run(run_copy).scene.objects] == ["thing", "object_2"]
    # a new grouping replaces them only when asked (Blender's Find Objects run twice)
    with pytest.raises(InputError, match="pass --replace"):
        run_segment(run, SegmentConfig(run=str(run_copy), from_masks=str(tmp_path), device="cpu"))


def test_auto_finds_the_target_without_masks(run_copy: Path, tmp_path: Path):
    """Geometry and salient-object votes (no masks read): object_1, the subject, is the target on the test
    views, and removing it by that name removes it."""
    scene = load_run_scene(run_copy)
    config = SegmentConfig(run=str(run_copy), auto=True, device="cpu", salient_weights=str(setup_weight("u2netp.onnx")))
    report = run_segment(load_run(run_copy), config)
    found = load_run_scene(run_copy)
    scores = proposal_scores([found.masks[i] for i in scene.test], [scene.masks[i] for i in scene.test],
                             [o.id for o in scene.objects])
    target = scores["objects"][scene.target.id]
    assert report["subject"] == "votes" and target["found"] == 1 and target["iou"] >= 0.6, (report, scores)
    sizes = {o["name"]: o["gaussians"] for o in json.loads((run_copy / "segments" / "objects.json").read_text())}
    assert report["subject_share"] == pytest.approx(sizes["object_1"] / len(load_run(run_copy).gaussians["means"]),
                                                    abs=1e-4)
    assert report["weak_evidence"] == [], report  # a whole object, a few percent of the scene
    assert report["test_psnr"] == round(json.loads((run_copy / "metrics.json").read_text())["psnr"], 2)
    removal = run_removal(RemovalConfig(run=str(run_copy), object="object_1", out=str(tmp_path / "r"), device="cpu"))
    assert removal["removed"] > 0


@pytest.mark.parametrize(("stats", "says"), [({"subject": None}, "no salient object"),
                                             ({"subject": "votes", "subject_share": 0.0128}, "1.3%"),
                                             ({"subject": "votes", "subject_share": 0.7776}, "78%"),
                                             ({"subject": "votes", "subject_share": 0.1296}, None),
                                             ({"subject": "votes", "subject_share": 0.0049, "solid_share": 0.014},
                                              "1.4% of the scene's Gaussians are opaque enough"),
                                             ({"subject": "votes", "subject_share": 0.0049, "solid_share": 0.014,
                                               "test_psnr": 14.5}, "1.4% of the scene's Gaussians are opaque enough"),
                                             ({"subject": "votes", "subject_share": 0.05, "solid_share": 0.021,
                                               "test_psnr": 39.63}, None),
                                             ({"subject": "votes", "subject_share": 0.17, "solid_share": 0.38}, None)])
def test_auto_says_when_its_subject_may_not_be_the_one(stats: dict, says: str | None):
    """The real captures' subjects: a patch of a plush toy's back (1.3% of the Gaussians), a skull with most of
    its room (78%), the statue (13%, right); a skull whose model was mostly transparent (1.4% of its Gaussians
    solid, 14.5 dB: whatever was found in it, the model is the problem); a generated livingroom that MCMC left mostly
    faint at a budget beyond its needs (2.1% solid) but that renders its test views at 39.6 dB, its subject right."""
    reasons = weak_evidence(stats)
    assert (reasons == []) if says is None else (len(reasons) == 1 and says in reasons[0]), reasons


def test_a_click_in_one_view_gives_the_object_under_it(run_copy: Path):
    """--point at the target's pixel centre in a training view (where the exact mask says it is), as a user
    clicks: the object made covers the target on the other views. A click the code refuses (nothing it can pick
    renders there) is answered with one line, and the user clicks in the next view; a click outside the image is
    refused with one line."""
    scene = load_run_scene(run_copy)
    refused = []
    for i in [i for i in scene.train if (scene.masks[i] == scene.target.id).sum() > 30]:
        rows, cols = np.nonzero(scene.masks[i] == scene.target.id)
        u, v = float(np.median(cols)) + 0.5, float(np.median(rows)) + 0.5
        try:
            report = run_segment(load_run(run_copy), SegmentConfig(run=str(run_copy), point=[u, v], name="clicked",
                                                                   view=scene.cameras[i].name, device="cpu"))
            break
        except InputError as refusal:
            assert "renders at --point" in str(refusal)
            refused.append(str(refusal))
    else:
        pytest.fail(f"every click on the target refused: {refused}")
    assert len(refused) <= 2, refused  # nine runs here refused none
    found = load_run_scene(run_copy)
    assert [o.name for o in found.objects] == ["clicked"]
    # the object under the click, mostly, on every view but the clicked one. Not the test view alone: the tiny
    # run has one, and at training seed 7 small objects' Gaussians render over the whole plush there (the pick
    # covered 445 of the target's 448 pixels in the clicked view, none in the test view). How much of the target
    # it covers varies with the tiny run (IoU 0.55 to 0.95 over training seeds 7, 10 and 13 here; the plush's
    # lowest Gaussians stay with the sofa's seat), what it takes beyond the target too (precision 0.55 at seed
    # 13, where a neighbour joined the plush's proposal, 0.89 to 0.96 at the others)
    others = [k for k in range(len(scene.cameras)) if k != i]
    picked = np.concatenate([found.masks[k].ravel() == 1 for k in others])
    truth = np.concatenate([scene.masks[k].ravel() == scene.target.id for k in others])
    precision, overlap = (picked & truth).sum() / max(picked.sum(), 1), iou(picked, truth)
    assert precision >= 0.5 and overlap >= 0.35, (precision, overlap, report, refused)
    with pytest.raises(InputError, match="lies outside"):
        run_segment(load_run(run_copy), SegmentConfig(run=str(run_copy), point=[1e4, 1.0], name="far",
                                                      view=scene.cameras[i].name, device="cpu"))


def test_a_click_takes_every_piece_that_meets_where_it_landed():
    """One object split into three touching pieces (a sliver nearest the click) and a second object a little
    away: the click takes the three, not the sliver alone nor the neighbour; with none in reach, the nearest."""
    rng = np.random.default_rng(0)
    body = rng.uniform([-0.1, 0.0, 0.0], [0.1, 0.2, 0.2], (2000, 3))
    means = np.concatenate([body, [[0.0, -0.01, 0.1]], [[0.3, 0.1, 0.1]]])
    ids = np.concatenate([np.where(body[:, 0] < 0, 1, 2), [3], [4]])  # 1, 2: halves; 3: the sliver; 4: another
    click = np.array([0.0, -0.015, 0.1])
    assert sorted(pieces_under(means, ids, click, reach=0.04)) == [1, 2, 3]
    assert list(pieces_under(means, ids, np.array([0.5, 0.1, 0.1]), reach=0.04)) == [4]


def test_a_wall_through_the_clicked_object_is_a_slice_of_it_and_a_wall_behind_it_stays():
    """A floor, a wall at x = -0.8 reaching across the orbit, and a ball on the floor holding a plane of its own
    Gaussians (x = 0, its solid ones 15 degrees off vertical on a tiny run: taken for a wall, the plush was no
    proposal and the click took a piece inside it). A click on the ball drops the slice and keeps the wall; the
    ball is then free of the supports. A click beside the wall keeps it."""
    from engine.geometry.scene_geometry import Supports, free_of
    from engine.segment.run import clicked_supports

    rng = np.random.default_rng(0)
    grid = np.linspace(-1.0, 1.0, 41)
    floor = np.stack(np.meshgrid(grid, grid, [0.0]), -1).reshape(-1, 3)
    wall = np.stack(np.meshgrid([-0.8], grid, np.linspace(0.0, 1.5, 31)), -1).reshape(-1, 3)
    ball = rng.normal(size=(600, 3))
    ball = 0.15 * ball / np.linalg.norm(ball, axis=1, keepdims=True) + [0.0, 0.0, 0.2]
    ys, zs = np.meshgrid(np.linspace(-0.12, 0.12, 9), np.linspace(0.08, 0.32, 9))
    slice_ = np.stack([np.zeros(ys.size), ys.ravel(), zs.ravel()], 1)
    means = np.concatenate([floor, wall, ball, slice_])
    frame, config = Frame(np.zeros(3), 1.0, np.array([0.0, 0.0, 1.0])), SegmentConfig()
    planes, walls = [(np.array([0.0, 0.0, 1.0]), 0.0)], [(np.array([1.0, 0.0, 0.0]), 0.8),
                                                          (np.array([1.0, 0.0, 0.0]), 0.0)]
    near, tol = np.ones(len(means), bool), config.plane_tol
    found = Supports(planes, walls, near, free_of(means, near, planes, walls, tol))
    kept = clicked_supports(found, means, np.ones(len(means)), np.array([0.0, -0.15, 0.2]), frame, config)
    assert [float(d) for _, d in kept.walls] == [0.8]
    on_ball = slice(len(floor) + len(wall), len(means))
    assert kept.free[on_ball].mean() > 0.95 and found.free[on_ball].mean() < 0.9
    # a click on a trophy a hand's width off the wall: the wall reaches far past it, so it stays a wall
    by_wall = clicked_supports(found, means, np.ones(len(means)), np.array([-0.7, 0.0, 0.6]), frame, config)
    assert 0.8 in [float(d) for _, d in by_wall.walls]


def test_a_click_takes_the_proposal_that_renders_under_it_not_a_hidden_or_faint_one():
    """A body (proposal 5) in front of the camera, a piece of the same size hidden behind it (2), a faint sliver
    in front of it that renders nothing (7), and 20 one-Gaussian proposals round it (more than an identity
    render holds): the click on the body gives 5; a click where only the support renders gives 0."""
    grid = np.stack(np.meshgrid(np.linspace(-0.3, 0.3, 8), np.linspace(-0.3, 0.3, 8), [0.0]), -1).reshape(-1, 3)
    rng = np.random.default_rng(0)
    crowd = np.concatenate([rng.uniform(-0.5, 0.5, (20, 2)), np.full((20, 1), 2.5)], axis=1)
    support = np.stack(np.meshgrid(np.linspace(-3, 3, 40), np.linspace(-3, 3, 40), [4.0]), -1).reshape(-1, 3)
    means = np.concatenate([grid + [0, 0, 2], grid + [0, 0, 3], [[0, 0, 1.9]] * 3, crowd, support])
    ids = np.concatenate([np.full(64, 5), np.full(64, 2), np.full(3, 7), np.arange(10, 30), np.zeros(1600, int)])
    splats = gaussians(means, np.full((len(means), 3), 0.5), scale=0.06)
    splats["opacities"][128:131] = -12.0  # the sliver: opacity 6e-6
    camera = Camera("0000.png", 64, 48, 60.0, 60.0, 32.0, 24.0, np.eye(3), np.zeros(3))
    assert rendered_under(splats, 0, ids, camera, (32.5, 24.5), torch.device("cpu")) == 5
    assert rendered_under(splats, 0, ids, camera, (3.5, 3.5), torch.device("cpu")) == 0
    # the pick is checked against what renders at the click: the body does, the hidden piece and the sliver not
    assert renders_at(splats, 0, ids == 5, camera, (32.5, 24.5), torch.device("cpu"))
    assert not renders_at(splats, 0, ids == 2, camera, (32.5, 24.5), torch.device("cpu"))
    assert not renders_at(splats, 0, ids == 7, camera, (32.5, 24.5), torch.device("cpu"))


def test_lifting_joins_segments_that_share_gaussians_whatever_their_ids():
    """Two views of two clusters of points, the ids swapped between the views: two objects, not four."""
    rng = np.random.default_rng(0)
    means = np.concatenate([rng.normal([-0.5, 0, 5], 0.1, (100, 3)), rng.normal([0.5, 0, 5], 0.1, (100, 3))])
    camera = Camera("0000.png", 64, 48, 60.0, 60.0, 32.0, 24.0, np.eye(3), np.zeros(3))
    depth = np.full((48, 64), 5.0, np.float32)
    left = np.zeros((48, 64), np.uint8)
    left[:, :32] = 7
    left[:, 32:] = 9
    right = np.where(left == 7, 3, 4).astype(np.uint8)  # the same two objects under other ids
    ids, stats, named = lift_masks(means, [camera, camera], [left, right], [depth, depth], rel_tol=0.1, join=0.5)
    assert stats["objects_found"] == 2 and stats["joined"] == 2 and named[1:].tolist() == [2, 2]
    assert len(set(ids[:100])) == 1 and len(set(ids[100:])) == 1 and ids[0] != ids[150]


def test_a_small_object_the_masks_name_in_enough_views_stays_and_a_small_fragment_goes():
    """The floor of Gaussians drops fragments, not an object a user's masks drew view after view (the tiny
    livingroom's small objects hold 11-17 Gaussians, named in 5-7 views)."""
    ids = np.repeat([0, 1, 2, 3], [50, 100, 12, 12])
    steady = np.array([False, True, True, False])  # object 2 named in enough views; object 3 once
    assert np.bincount(renumber(ids, 20, None, steady)).tolist() == [62, 100, 12]
    assert np.bincount(renumber(ids, 20)).tolist() == [74, 100]


def test_components_join_what_touches_and_nothing_else():
    label = components(6, np.array([0, 1, 4]), np.array([1, 2, 5]))
    assert label.tolist() == [0, 0, 0, 3, 4, 4]
    rng = np.random.default_rng(0)
    blobs = np.concatenate([rng.uniform(0, 1, (500, 3)), rng.uniform(0, 1, (500, 3)) + [3, 0, 0]])
    voxel, label = voxel_components(blobs, 0.25)
    parts = label[voxel]
    assert len(set(parts[:500])) == 1 and len(set(parts[500:])) == 1 and parts[0] != parts[-1]


def test_a_figure_split_at_the_waist_is_one_subject_on_its_boulder():
    """The statue capture at 5b804af: its figure's Gaussians came apart at the waist (a gap of 1.5 voxels), the legs
    went with the boulder as the largest salient piece, and the upper body stayed in the scene. The pieces stacked on
    one another are one: the whole figure is the subject, and the boulder a pedestal it stands on."""
    rng = np.random.default_rng(0)
    voxel, up = 0.1, np.array([0.0, 0.0, 1.0])

    def box(low, high, count):
        return rng.uniform(low, high, (count, 3))

    boulder = box([-1.5, -1.5, 0.0], [1.5, 1.5, 1.0], 40000)
    legs, body = box([-0.25, -0.25, 1.0], [0.25, 0.25, 1.8], 3000), box([-0.3, -0.3, 1.95], [0.3, 0.3, 3.0], 5000)
    means = np.concatenate([boulder, legs, body])
    colours = np.repeat([[0.8, 0.5, 0.5], [0.1, 0.3, 0.2], [0.1, 0.3, 0.2]], [40000, 3000, 5000], axis=0)
    every = np.ones(len(means), bool)
    chosen, why = subject(np.ones(len(means)), means, colours, every, every, every, up, voxel, 0.5)
    figure = np.repeat([False, True, True], [40000, 3000, 5000])
    assert why["pedestal"] and (chosen == figure).all(), (why, chosen[:40000].mean(), chosen[40000:].mean())


def test_the_plate_a_figure_stands_on_goes_with_it_and_the_pedestal_stays():
    """The statue capture at 728921d: the figure's bronze base plate lay in the boulder's top voxel slice, below the
    pedestal's cut, and stayed on the boulder as a dark patch. The plate, of the figure's colour and touching it,
    goes with the figure; the boulder's top in the same slice, and a bronze plaque lower on its side, stay."""
    rng = np.random.default_rng(0)
    voxel, up = 0.1, np.array([0.0, 0.0, 1.0])

    def box(low, high, count):
        return rng.uniform(low, high, (count, 3))

    boulder = box([-1.5, -1.5, 0.0], [1.5, 1.5, 0.95], 40000)
    plate = box([-0.4, -0.4, 0.95], [0.4, 0.4, 0.99], 1500)  # in the boulder's top slice (0.9 to 1.0)
    figure = box([-0.25, -0.25, 1.0], [0.25, 0.25, 3.0], 6000)
    plaque = np.c_[np.full(500, 1.5), rng.uniform([-0.3, 0.4], [0.3, 0.6], (500, 2))]  # on the side, mid-height
    means = np.concatenate([boulder, plate, figure, plaque])
    part = np.repeat(np.arange(4), [40000, 1500, 6000, 500])
    colours = np.where((part == 0)[:, None], [0.8, 0.5, 0.5], [0.1, 0.3, 0.2])
    every = np.ones(len(means), bool)
    chosen, why = subject(np.ones(len(means)), means, colours, every, every, every, up, voxel, 0.5)
    taken = [chosen[part == k].mean() for k in range(4)]  # boulder, plate, figure, plaque
    assert why["pedestal"] and taken[1] == 1.0 and taken[2] == 1.0 and taken[0] == 0.0 and taken[3] == 0.0, (
        why, taken)


def test_a_toy_whose_body_has_few_opaque_gaussians_keeps_its_tracks():
    """tabletop_s5 at 748ee7a (300,000 Gaussians, mostly faint): the toy's tracks were opaque and its body above them
    held few opaque Gaussians, so the salient opaque piece the subject starts from had a footprint below three times
    that above, and the tracks were cut off as a pedestal (IoU 0.47, 0.87 with them). The cut must hold on the whole
    piece the growth reaches, faint Gaussians too: the tracks are as wide as the body, and stay with it."""
    rng = np.random.default_rng(0)
    voxel, up = 0.05, np.array([0.0, 0.0, 1.0])
    tracks = rng.uniform([-0.35, -0.3, 0.0], [0.35, 0.3, 0.25], (6000, 3))
    body = rng.uniform([-0.3, -0.25, 0.25], [0.3, 0.25, 0.6], (6000, 3))
    means = np.concatenate([tracks, body])
    colours = np.repeat([[0.35, 0.33, 0.32], [0.8, 0.65, 0.3]], 6000, axis=0)  # grey tracks, a yellow body
    solid = np.r_[np.ones(6000, bool), np.zeros(6000, bool)]
    solid[6000:] = (np.abs(body[:, :2]) < 0.05).all(1)  # the body opaque only in a narrow core (its cab)
    every = np.ones(len(means), bool)
    chosen, why = subject(np.ones(len(means)), means, colours, solid, every, every, up, voxel, 0.5)
    assert not why["pedestal"] and chosen.all(), (why, chosen[:6000].mean(), chosen[6000:].mean())


def test_a_pedestal_cut_through_its_rounded_shoulder_gives_way_to_the_slice_above():
    """The statue capture at e41a552: the lowest slice that passed on the opaque piece lay in the boulder's rounded
    top, whose faint Gaussians reach wider than its opaque core, so the grown piece there was 2.4 times wider below
    than above (under 2.5), the cut was dropped, and the boulder went with the figure (38% of the scene). The slice
    above the shoulder passes on both (4.4): the figure alone is the subject, the shoulder stays with the boulder."""
    rng = np.random.default_rng(0)
    voxel, up = 0.1, np.array([0.0, 0.0, 1.0])
    boulder = rng.uniform([-1.5, -1.5, 0.0], [1.5, 1.5, 0.8], (40000, 3))
    core = rng.uniform([-0.6, -0.6, 0.8], [0.6, 0.6, 0.9], (500, 3))  # the shoulder's opaque part
    faint = rng.uniform([-1.2, -1.2, 0.8], [1.2, 1.2, 0.9], (3000, 3))  # ... and its faint, wider one
    figure = rng.uniform([-0.25, -0.25, 0.9], [0.25, 0.25, 3.0], (6000, 3))
    means = np.concatenate([boulder, core, faint, figure])
    part = np.repeat(np.arange(4), [40000, 500, 3000, 6000])
    colours = np.where((part == 3)[:, None], [0.1, 0.3, 0.2], [0.8, 0.5, 0.5])
    every = np.ones(len(means), bool)
    chosen, why = subject(np.ones(len(means)), means, colours, part != 2, every, every, up, voxel, 0.5)
    taken = [chosen[part == k].mean() for k in range(4)]  # boulder, core, faint shoulder, figure
    assert why["pedestal"] and taken == [0.0, 0.0, 0.0, 1.0], (why, taken)


def test_a_figure_s_base_of_patina_goes_whole_down_to_the_boulder_and_the_boulder_s_top_stays():
    """The statue capture at 274f783: the cut passed on footprint from the boulder's top up, but on colour only three
    slices higher, since the bronze base's patina (half of it lighter than the figure) kept the two sides' means
    close; the base's Gaussians under the cut went only where, each alone, they were nearer the figure's colour than
    the whole boulder's, and the lighter half stayed on the boulder as a green ghost. Under the figure's feet, down to
    the boulder's top, each slice goes while its Gaussians together have the figure's colour more than the boulder
    top's: the whole base goes; the boulder's top around it, its colour, stays."""
    rng = np.random.default_rng(0)
    voxel, up = 0.1, np.array([0.0, 0.0, 1.0])
    boulder = rng.uniform([-2.0, -2.0, 0.0], [2.0, 2.0, 0.8], (60000, 3))
    top = rng.uniform([-0.9, -0.9, 0.8], [0.9, 0.9, 1.0], (80000, 3))
    top = top[(np.abs(top[:, :2]) > 0.6).any(1)][:26000]  # the boulder's top around the base
    base = rng.uniform([-0.35, -0.35, 0.8], [0.35, 0.35, 1.2], (3000, 3))
    figure = rng.uniform([-0.25, -0.25, 1.2], [0.25, 0.25, 3.0], (6000, 3))
    means = np.concatenate([boulder, top, base, figure])
    part = np.repeat(np.arange(4), [len(boulder), len(top), len(base), len(figure)])
    colours = np.array([[0.7, 0.6, 0.55], [0.7, 0.6, 0.55], [0.22, 0.25, 0.23], [0.15, 0.2, 0.18]])[part]
    colours[(part == 2) & (rng.random(len(means)) < 0.5)] = [0.47, 0.52, 0.49]  # the patina's lighter half
    colours += rng.normal(0, 0.05, colours.shape)
    every = np.ones(len(means), bool)
    chosen, why = subject(np.ones(len(means)), means, colours, every, every, every, up, voxel, 0.5)
    taken = [float(chosen[part == k].mean()) for k in range(4)]  # boulder, its top, base, figure
    assert why["pedestal"] and taken == [0.0, 0.0, 1.0, 1.0], (why, taken)  # before: the base 0.75


def test_a_plaque_many_voxels_wide_goes_whole_with_its_head_and_the_picture_beside_it_stays():
    """wallmount_s5 at f1affc9 (300,000 Gaussians, so the voxel is 0.02 R, not the tiny run's spacing): the subject
    was the head alone, IoU 0.47. Growing six steps of a voxel reached six voxels; here the plaque's salient
    Gaussians, in the wall's band (not free), reach 15 voxels beyond the head. They go whole; a salient picture two
    voxels across the bare wall stays."""
    rng = np.random.default_rng(0)
    voxel, up = 0.01, np.array([0.0, 0.0, 1.0])
    head = rng.uniform([-0.05, 0.005, 0.1], [0.05, 0.1, 0.2], (4000, 3))
    plaque = rng.uniform([-0.2, 0.0, 0.0], [0.2, 0.005, 0.3], (12000, 3))  # on the wall (y = 0), in its band
    picture = rng.uniform([0.22, 0.0, 0.0], [0.4, 0.005, 0.3], (8000, 3))  # 2 voxels of bare wall from the plaque
    means = np.concatenate([head, plaque, picture])
    part = np.repeat(np.arange(3), [4000, 12000, 8000])
    colours = np.where((part == 0)[:, None], [0.6, 0.4, 0.4], [0.5, 0.3, 0.1])
    every, free = np.ones(len(means), bool), part == 0
    chosen, why = subject(np.ones(len(means)), means, colours, every, free, every, up, voxel, 0.5)
    taken = [chosen[part == k].mean() for k in range(3)]  # head, plaque, picture
    assert taken == [1.0, 1.0, 0.0], (why, taken)  # six steps of a voxel: the plaque 0.32


def test_a_plaque_the_salient_maps_light_faintly_goes_with_its_head_and_the_bare_wall_stays():
    """wallmount_s5 at 7cf9ed7: the plaque's wood voted salient in 0.2-0.4 of the views seeing it, its head in 0.8
    and more, and the growth crossed only Gaussians voting min_vote (0.5): the head alone, IoU 0.47. The growth
    needs GROW_VOTE of them; the bare wall around (0.05) and a picture beyond it stay."""
    rng = np.random.default_rng(1)
    voxel, up = 0.01, np.array([0.0, 0.0, 1.0])
    head = rng.uniform([-0.05, 0.005, 0.1], [0.05, 0.1, 0.2], (4000, 3))
    plaque = rng.uniform([-0.15, 0.0, 0.0], [0.15, 0.005, 0.3], (9000, 3))  # on the wall (y = 0), in its band
    wall = np.c_[rng.uniform(-0.6, 0.6, 30000), rng.uniform(0.0, 0.005, 30000), rng.uniform(-0.3, 0.6, 30000)]
    wall = wall[(np.abs(wall[:, 0]) > 0.16) | (wall[:, 2] < -0.01) | (wall[:, 2] > 0.31)]  # around the plaque
    picture = rng.uniform([0.3, 0.006, 0.0], [0.5, 0.01, 0.3], (6000, 3))  # on the wall, salient
    means = np.concatenate([head, plaque, wall, picture])
    part = np.repeat(np.arange(4), [4000, 9000, len(wall), 6000])
    votes = np.array([0.9, 0.3, 0.05, 0.9])[part]
    colours = np.where((part == 0)[:, None], [0.6, 0.4, 0.4], [0.5, 0.3, 0.1])
    every, free = np.ones(len(means), bool), part == 0
    chosen, why = subject(votes, means, colours, every, free, every, up, voxel, 0.5)
    taken = [round(float(chosen[part == k].mean()), 3) for k in range(4)]  # head, plaque, wall, picture
    assert taken == [1.0, 1.0, 0.0, 0.0], (why, taken)  # over min_vote only: the plaque 0.0


def test_the_salient_sheet_a_figure_stands_on_and_its_shadow_stay_on_the_floor():
    """The growth goes into no level support's band: on the tiny tabletop run the salient mat under the toy went
    with it (IoU 0.13), on the tiny statue and livingroom runs the ground at the object's foot. A sheet under the
    figure voting as salient as the figure, and its shadow voting as faintly as a plaque, stay; the figure goes
    whole."""
    rng = np.random.default_rng(2)
    voxel, up = 0.01, np.array([0.0, 0.0, 1.0])
    figure = rng.uniform([-0.05, -0.05, 0.005], [0.05, 0.05, 0.3], (6000, 3))
    sheet = rng.uniform([-0.2, -0.2, -0.004], [0.0, 0.2, 0.004], (8000, 3))  # on the floor (z = 0), under it
    shadow = rng.uniform([0.0, -0.06, -0.004], [0.25, 0.06, 0.004], (5000, 3))  # on the floor, beside it
    floor = rng.uniform([-0.6, -0.6, -0.004], [0.6, 0.6, 0.004], (30000, 3))
    floor = floor[((floor[:, 0] < -0.21) | (floor[:, 0] > 0.26) | (np.abs(floor[:, 1]) > 0.21))]
    means = np.concatenate([figure, sheet, shadow, floor])
    part = np.repeat(np.arange(4), [6000, 8000, 5000, len(floor)])
    votes = np.array([0.9, 0.9, 0.3, 0.05])[part]
    colours = np.where((part == 0)[:, None], [0.6, 0.4, 0.4], [0.3, 0.3, 0.3])
    every, free, level = np.ones(len(means), bool), part == 0, np.abs(means[:, 2]) < 0.005
    chosen, why = subject(votes, means, colours, every, free, every, up, voxel, 0.5, level=level)
    taken = [round(float(chosen[part == k].mean()), 3) for k in range(4)]  # figure, sheet, shadow, floor
    assert taken == [1.0, 0.0, 0.0, 0.0], (why, taken)  # growing into the floor's band: sheet and shadow 1.0


def test_a_noisy_table_top_is_peeled_off_the_objects_on_it():
    """A tiny CPU run left its table top a slab of Gaussians up to 3 plane bands thick, which joined the plush
    and the table into one piece wider than the orbit (scenery): peeling wider bands splits the objects off,
    and what peeling frees under the table (nothing rests on a plane there) stays scenery."""
    rng = np.random.default_rng(0)
    tol, size, up = 0.02, 0.02, np.array([0.0, 0.0, 1.0])
    slab = np.c_[rng.uniform(-0.5, 0.5, (8000, 2)), rng.choice([-1, 1], 8000) * rng.uniform(tol, 1.75 * tol, 8000)]
    angle, radius = rng.uniform(0, 2 * np.pi, 1600), 0.07 * np.sqrt(rng.uniform(0, 1, 1600))
    blobs = np.c_[radius * np.cos(angle) + np.repeat([-0.25, 0.25], 800), radius * np.sin(angle),
                  rng.uniform(tol, 0.2, 1600)]
    clumps = np.c_[rng.uniform(-0.03, 0.03, (400, 2)) + np.repeat([[-0.4, -0.4], [0.4, 0.4]], 200, axis=0),
                   rng.uniform(-0.08, -0.03, 400)]  # under the table top, touching the slab
    points = np.concatenate([slab, blobs, clumps])
    part = np.repeat([0, 1, 2, 3], [len(slab), 800, 800, len(clumps)])  # slab, left blob, right blob, clumps
    points, part = points[np.abs(points[:, 2]) >= tol], part[np.abs(points[:, 2]) >= tol]  # off the band
    first, _ = split_pieces(points, points[:, 2:], [tol], size, 2 * size, up, 0.8)
    assert not first.any()  # one piece, as wide as the table
    ids, peeled = split_pieces(points, points[:, 2:], [tol, 2 * tol, 3 * tol], size, 2 * size, up, 0.8)
    high = points[:, 2] >= 3 * tol
    left, right = np.unique(ids[(part == 1) & high]), np.unique(ids[(part == 2) & high])
    assert len(left) == 1 and len(right) == 1 and left[0] != right[0] and 0 not in (left[0], right[0])
    assert set(np.unique(ids[ids > 0])) == {left[0], right[0]}  # the slab and the clumps: background
    assert peeled[part == 0].all()


def test_support_planes_are_found_in_any_frame():
    """A floor and a table top, tilted 30 degrees and scaled by 0.3 as SfM may give them: both found."""
    rng = np.random.default_rng(1)
    floor = np.c_[rng.uniform(-2, 2, (3000, 2)), rng.normal(0, 0.003, 3000)]
    table = np.c_[rng.uniform(-0.6, 0.6, (1500, 2)), 0.75 + rng.normal(0, 0.003, 1500)]
    clutter = rng.uniform([-0.3, -0.3, 0.75], [0.3, 0.3, 1.2], (800, 3))
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    tilt = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    points = 0.3 * np.concatenate([floor, table, clutter]) @ tilt.T
    up = tilt @ np.array([0.05, 0.0, 1.0]) / np.linalg.norm([0.05, 0, 1])  # the cameras' up, 3 degrees off
    planes = support_planes(points, up, tol=0.003, share=0.05)
    heights = sorted(-d / 0.3 for _, d in planes)
    assert len(planes) == 2 and np.allclose(heights, [0, 0.75], atol=0.01), heights
    assert all(n @ (tilt @ [0, 0, 1]) > np.cos(np.radians(1)) for n, _ in planes)


def test_a_slice_of_an_object_with_floaters_at_its_height_is_no_plane():
    """A statue's plinth top (radius 0.1) and some floaters far off at the same height held a tiny run's
    statue as a second "plane" that cut it in two (90th-percentile spread 0.77 R); the median says 0.09 R."""
    rng = np.random.default_rng(2)
    angle = rng.uniform(0, 2 * np.pi, 3000)
    floor = np.c_[rng.uniform(-1.5, 1.5, (3000, 2)), rng.normal(0, 0.003, 3000)]
    statue = np.c_[0.1 * np.cos(angle), 0.1 * np.sin(angle), rng.uniform(0, 1, 3000)]
    plinth = np.c_[rng.uniform(-0.07, 0.07, (400, 2)), np.full(400, 0.5)]
    floaters = np.c_[0.9 * np.cos(angle[:60]), 0.9 * np.sin(angle[:60]), np.full(60, 0.5)]
    points = np.concatenate([floor, statue, plinth, floaters])
    planes = support_planes(points, np.array([0.0, 0.0, 1.0]), tol=0.01, share=0.05, min_radius=0.15)
    assert [round(-d, 2) for _, d in planes] == [0.0]


def test_a_wall_with_a_rail_along_it_holds_no_level_plane():
    """A scene that is mostly wall (the wall-mounted family, its floor out of view) with a dense rail of points
    along it at one height: that slab is as long as a floor and passes is_thin, but it is a strip 0.02 wide, not
    an area; taken for a floor it left nothing of a tiny run's trophy free (segment --auto found no subject)."""
    rng = np.random.default_rng(3)
    wall = np.c_[rng.uniform(-1, 1, 4000), rng.normal(0, 0.004, 4000), rng.uniform(0, 1.5, 4000)]
    rail = np.c_[rng.uniform(-1, 1, 600), rng.normal(0, 0.004, 600), 1.2 + rng.normal(0, 0.004, 600)]
    up = np.array([0.0, 0.0, 1.0])
    assert support_planes(np.concatenate([wall, rail]), up, tol=0.02, share=0.05, min_radius=0.15) == []
    floor = np.c_[rng.uniform(-1, 1, 1500), rng.uniform(-1.0, 0.0, 1500), rng.normal(0, 0.004, 1500)]
    planes = support_planes(np.concatenate([wall, rail, floor]), up, tol=0.02, share=0.05, min_radius=0.15)
    assert [round(-d, 2) for _, d in planes] == [0.0]


def test_a_level_slab_across_a_wall_and_its_trophy_is_a_strip_of_the_wall_and_a_floor_is_not():
    """On a wall-mounted run at 160x120 two level slabs through the wall and the trophy's head (78-86% wall) were
    taken for floors at the trophy's height; its head came out in three objects (target IoU 0.13)."""
    rng = np.random.default_rng(4)
    wall = np.c_[rng.uniform(-1, 1, 4000), rng.normal(0, 0.004, 4000), rng.uniform(0, 1.5, 4000)]
    head = np.c_[rng.normal(0, 0.08, (300, 1)), rng.uniform(0.02, 0.2, 300), rng.normal(1.2, 0.08, 300)]
    floor = np.c_[rng.uniform(-1, 1, 2000), rng.uniform(-1.5, 0, 2000), rng.normal(0, 0.004, 2000)]
    points, up, walls = np.concatenate([wall, head, floor]), np.array([0.0, 0.0, 1.0]), [(np.array([0.0, 1, 0]), 0.0)]
    assert strip_of_walls(points, (up, -1.2), walls, tol=0.02)
    assert not strip_of_walls(points, (up, 0.0), walls, tol=0.02)


def test_the_level_of_a_strip_is_the_cameras_up():
    """A strip (a level slab through a wall: long, thin across the wall, as tall as the slab) has no plane of its
    own; the least-squares refit of its points leaned 89 degrees from up and set every level plane's normal."""
    rng = np.random.default_rng(3)
    strip = np.c_[rng.uniform(-1, 1, 600), rng.normal(0, 0.002, 600), rng.normal(1.2, 0.008, 600)]
    assert level_normal(strip, np.array([0.0, 0.0, 1.0]), 0.02).tolist() == [0.0, 0.0, 1.0]


def test_association_is_scored_against_perturbed_masks():
    """perturb_masks shuffles and splits/merges; a result that equals the truth scores 1, a shuffled one less."""
    rng = np.random.default_rng(0)
    truth = [np.zeros((20, 30), np.uint8) for _ in range(4)]
    for t in truth:
        t[2:9, 2:12], t[11:18, 15:28] = 1, 2
    given, owners = perturb_masks(truth, rng, share=0.5)
    assert any(set(np.unique(g)) != {0, 1, 2} for g in given)  # something was shuffled, split or merged
    assert association_accuracy(given, owners, truth) == 1.0
    swapped = [np.where(t == 1, 2, np.where(t == 2, 1, 0)).astype(np.uint8) for t in truth[:2]] + truth[2:]
    assert association_accuracy(given, owners, swapped) < 1.0
    assert iou(truth[0] == 1, truth[0] == 1) == 1.0


def test_read_back_masks_are_instance_pngs(run_copy: Path, tmp_path: Path):
    means = load_run(run_copy).gaussians["means"].numpy()
    lo, hi = np.percentile(means, 30, axis=0), np.percentile(means, 70, axis=0)
    run_segment(load_run(run_copy), SegmentConfig(run=str(run_copy), box=[*lo, *hi], device="cpu"))
    mask = read_png(run_copy / "segments" / "masks" / "0000.png", kind="mask")
    assert mask.dtype == np.uint8 and set(np.unique(mask)) <= {0, 1}


def test_a_thin_figure_sliced_by_a_plane_is_still_the_whole_subject():
    """The shared statue capture at 766477c: a vertical plane through its thin bronze figure was taken for a wall
    (91% of the plane's solid Gaussians voted salient), so the figure was not free of the supports and `segment
    --auto` took its legs and left its chest and head standing. The plane through the salient figure is no wall;
    the wall behind, with a salient plaque on it, stays one."""
    rng = np.random.default_rng(0)
    ground = np.c_[rng.uniform(-1, 1, (20000, 2)), np.zeros(20000)]
    boulder = rng.uniform([-0.3, -0.3, 0.0], [0.3, 0.3, 0.3], (8000, 3))
    figure = rng.uniform([-0.1, -0.012, 0.3], [0.1, 0.012, 1.1], (6000, 3))  # a slab a voxel thick
    wall = np.c_[np.full(10000, -0.9), rng.uniform([-0.8, 0.0], [0.8, 1.2], (10000, 2))]
    plaque = np.c_[np.full(600, -0.89), rng.uniform([-0.1, 0.5], [0.1, 0.7], (600, 2))]
    means = np.concatenate([ground, boulder, figure, wall, plaque])
    part = np.repeat(np.arange(5), [20000, 8000, 6000, 10000, 600])
    votes = np.isin(part, [1, 2, 4]).astype(float)  # boulder, figure and plaque salient
    colours = np.where(part[:, None] == 1, [0.8, 0.5, 0.5], [0.1, 0.3, 0.2])
    opacity, frame, config = np.ones(len(means)), Frame(np.zeros(3), 1.0, np.array([0.0, 0.0, 1.0])), SegmentConfig()
    supports = find_supports(means, opacity, frame, config)
    assert len(supports.walls) == 2 and not supports.free[part == 2].any()  # the wall, and a plane through the figure
    solid = opacity >= config.solid
    kept = subject_supports(supports, means, solid, votes, frame, config)
    assert len(kept.walls) == 1 and abs(kept.walls[0][0][0]) > 0.99  # the wall behind (normal along x) stays
    chosen, why = subject(votes, means, colours, solid, kept.free, kept.near, frame.up, config.voxel, 0.5)
    taken = [chosen[part == k].mean() for k in range(5)]  # ground, boulder, figure, wall, plaque
    assert why["pedestal"] and taken[2] > 0.95 and taken[1] < 0.01 and not chosen[np.isin(part, [0, 3, 4])].any(), (
        why, taken)


def test_what_stands_on_the_floor_is_free_of_it_whichever_way_the_cameras_lean():
    """SfM's up (the cameras' mean) is only roughly up. With it 10 degrees off the floor's normal, a box 6 plane bands
    tall standing 0.75 R out from the centre lay below the floor by the cameras' up and none of it was free; measured
    along the floor's own normal, all of it above the floor's band is."""
    rng = np.random.default_rng(0)
    floor = np.c_[rng.uniform(-1, 1, (20000, 2)), np.zeros(20000)]
    box = rng.uniform([-0.8, -0.05, 0.0], [-0.7, 0.05, 0.12], (2000, 3))
    lean = np.radians(10)
    frame = Frame(np.zeros(3), 1.0, np.array([np.sin(lean), 0.0, np.cos(lean)]))
    means = np.concatenate([floor, box])
    supports = find_supports(means, np.ones(len(means)), frame, SegmentConfig())
    assert len(supports.planes) == 1 and abs(supports.planes[0][0][2]) > 0.999  # the floor, by its own normal
    above = box[:, 2] > 0.02 * 1.5
    assert supports.free[len(floor):][above].mean() > 0.95
