"""Completion: every method over the one loop on the tiny run's removal, resumable, and scored."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
from conftest import setup_weight

from engine.base.errors import InputError
from engine.inpaint.run import InpaintConfig, run_inpaint
from engine.io.image_io import read_png, write_png
from engine.io.masks import dilate
from engine.train.trained_run import load_run_scene


@pytest.fixture
def stages(tiny_stages: dict[str, Path]) -> dict[str, Path]:
    return tiny_stages

def errors_toward(run_dir: Path, views: list[int], masks: Path, targets: Path, before: Path) -> tuple[float, float]:
    """Mean absolute error (0-255) inside `masks` of the given training views between the targets and (a) the
    completed run's renders, (b) the `before` images (the removed, unfilled renders): a completion that put
    the 2D fill into 3D has (a) < (b). Why not m-PSNR on the test views: the tiny runs' one or two test views
    are too few, and our holes cover little of their true holes (IoU 0.2-0.4), so their m-PSNR moves by a dB
    either way with the training seed (measured: Init-fsr 21.7-24.3 dB against the unfilled 22.5-23.6 over
    five runs; docs/BENCHMARKS.md)."""
    from engine.render.render_views import render_pictures
    from engine.train.trained_run import load_run

    run = load_run(run_dir)
    cameras = [run.scene.cameras[i] for i in views]
    after, unfilled = [], []
    for camera, picture in zip(cameras, render_pictures(run.gaussians, cameras, run.sh_degree, "cpu"), strict=True):
        mask = read_png(masks / camera.name, kind="mask") > 0
        target = read_png(targets / camera.name)[mask].astype(float)
        after.append(np.abs(picture.rgb[mask] - target).mean())
        unfilled.append(np.abs(read_png(before / camera.name)[mask] - target).mean())
    return float(np.mean(after)), float(np.mean(unfilled))


def with_hole(scene, masks: Path) -> list[int]:
    return [i for i in scene.train if (read_png(masks / scene.cameras[i].name, kind="mask") > 0).any()]


def painted_fill(fsr: Path, holes: Path, out: Path) -> Path:
    """The fsr folder with every hole painted one flat colour far from the scene's: fsr's fill on the tiny run
    is within 10 grey levels of the unfilled render in 71% of the hole pixels (measured), so whether a
    completion carried it into 3D cannot be told from its renders; a fill as any user's own inpainter might
    hand over (`complete --inpainted`) that differs everywhere can."""
    import shutil

    shutil.copytree(fsr, out)
    for image in sorted((out / "images").glob("*.png")):
        hole = read_png(holes / image.name, kind="mask") > 0
        if hole.any():
            rgb = read_png(image)
            rgb[hole] = (230, 30, 200)
            write_png(image, rgb)
    return out


def test_init_completion_trains_on_the_inpainted_views_and_carries_the_fill_into_3d(stages, tmp_path):
    """Init with the run's own 800 steps: the training images are the inpainted renders inside the object's
    region and the holes as inpainted (whose band the photos contradict reaches past the region; with the input
    images kept there, the holes' pixels beside the region were not the fill) and the input images elsewhere; the
    new scene's renders inside the holes moved toward the fill.
    m-PSNR is scored beside the unfilled scene's (see errors_toward for why it is not asserted)."""
    from engine.complete.run import CompleteConfig, run_complete
    from engine.complete.scoring import score_run
    from engine.metrics.scores import ScoreConfig, Scorer
    from engine.train.trained_run import load_run

    fsr = stages["work"] / "fsr-for-init"
    run_inpaint(InpaintConfig(run=str(stages["run"]), inpainter="fsr", removed=str(stages["removed"]),
                              holes=str(stages["holes"]), out=str(fsr), dilate=1))
    # painted in the part no view saw, which is one region in 3D: the band the photos contradict around it is each
    # view's own evidence, which no 3D scene paints in every view (painted too, at 8c6f425: 66.9 against 83.0, a
    # ratio of 0.81)
    unseen = stages["holes"] / "unseen"
    inpainted = painted_fill(fsr, unseen, tmp_path / "painted")
    out = tmp_path / "Init-fsr"
    report = run_complete(CompleteConfig(run=str(stages["run"]), method="init", inpainter="fsr",
                                         inpainted=str(inpainted), removed=str(stages["removed"]), out=str(out),
                                         device="cpu", options={"warm": False}))
    assert report["method"] == "Init-fsr" and (out / "scores.json").is_file()
    assert np.isfinite(report["scores"]["m_psnr"]) and np.isfinite(report["removed_scores"]["m_psnr"])
    assert report["scores"]["lpips"] is None and "LPIPS_BACKBONE" in report["unavailable"]["lpips"]
    # scored on the original scene's test views, which the training scene copies: the same as its own, read back
    again = score_run(out / "run", Scorer(ScoreConfig(device="cpu"))).values
    assert all(again[k] == pytest.approx(report["scores"][k], abs=1e-9) for k in ("psnr", "m_psnr", "ssim", "m_ssim"))
    trained = load_run(out / "run")
    assert trained.scene.target is None  # the removed object is background in the training scene
    assert all(not (m == 1).any() for m in trained.scene.masks)
    scene, original = trained.scene, load_run_scene(stages["run"])
    for i in scene.train:  # the fill inside the object's region and its relit shadow, the input image elsewhere
        name = scene.cameras[i].name
        hole = read_png(stages["holes"] / name, kind="mask") > 0
        region = read_png(stages["removed"] / "masks" / name, kind="mask") > 0
        shadow = read_png(stages["removed"] / "effects" / name, kind="mask") > 0
        filled = read_png(inpainted / "images" / name)
        assert (scene.images[i][hole] == filled[hole]).all()
        assert (scene.images[i][shadow] == filled[shadow]).all()
        far = ~dilate(region | shadow | hole, 4)
        assert (scene.images[i][far] == original.images[i][far]).all()
    after, before = errors_toward(out / "run", with_hole(scene, unseen), unseen, inpainted / "images",
                                  stages["removed"] / "images")
    # a scene that never saw the painted fill stays at the unfilled render's error (a ratio of 1.0); measured on tiny
    # runs of training seeds 0-4 (CI's machine makes a run of its own): 0.55 / 0.49 / 0.54 / 0.48 / 0.77, the highest
    # where floaters left unseen patches on the wall that each view holds apart; with the graft dropping the new
    # Gaussians wider than their hole instead of shrinking them (hole_region.fit_to_holes): 0.55 / 1.00 / 1.04 on
    # seeds 0-2, and 1.07 on CI
    assert after < 0.85 * before


def test_ref_carries_one_views_fill_into_the_others_holes_and_trains_on_it(stages, tmp_path):
    """Ref-fsr: one training view's fill, placed by its depth, lands in the other views' holes, then trains
    as Init does. Measured: 23% of the hole pixels carried here (the tiny run's holes are ragged, IoU 0.2-0.4,
    many off the table), 97-99% on the 320x240 GPU runs (docs/BENCHMARKS.md)."""
    import json

    from engine.complete.run import CompleteConfig, run_complete

    inpainted = stages["work"] / "fsr-for-ref"
    run_inpaint(InpaintConfig(run=str(stages["run"]), inpainter="fsr", removed=str(stages["removed"]),
                              holes=str(stages["holes"]), out=str(inpainted)))
    out = tmp_path / "Ref-fsr"
    report = run_complete(CompleteConfig(run=str(stages["run"]), method="reference", inpainter="fsr",
                                         inpainted=str(inpainted),
                                         removed=str(stages["removed"]), holes=str(stages["holes"]), out=str(out),
                                         steps=50, device="cpu", options={"warm": False}))
    assert report["method"] == "Ref-fsr" and np.isfinite(report["scores"]["m_psnr"])
    carried = json.loads((out / "scene" / "reference_fill.json").read_text())
    assert carried["reference"] and carried["carried_share"] > 0.1, carried


def test_direct_inpaints_the_object_region_of_the_input_images_and_completes_from_them(stages, tmp_path):
    from engine.complete.run import CompleteConfig, run_complete

    inpainted = stages["work"] / "direct-fsr"
    grow = run_inpaint(InpaintConfig(run=str(stages["run"]), inpainter="fsr", source="input",
                                     removed=str(stages["removed"]), out=str(inpainted)))["dilate_px"]
    scene = load_run_scene(stages["run"])
    for i, camera in enumerate(scene.cameras):
        region = read_png(stages["removed"] / "masks" / camera.name, kind="mask") > 0
        region |= read_png(stages["removed"] / "effects" / camera.name, kind="mask") > 0  # and its shadow
        region = dilate(region, grow)  # grown as the holes are: its blended silhouette goes too
        filled = read_png(inpainted / "images" / camera.name)
        assert (filled[~region] == scene.images[i][~region]).all()
        assert not region.any() or (filled[region] != scene.images[i][region]).any()
    masks = stages["removed"] / "masks"  # the object's region: where the input images were painted over
    painted = painted_fill(inpainted, masks, tmp_path / "painted")  # fsr's fill is near the unfilled render
    out = tmp_path / "direct"
    report = run_complete(CompleteConfig(run=str(stages["run"]), method="direct", inpainter="fsr",
                                         inpainted=str(painted),
                                         removed=str(stages["removed"]), out=str(out), device="cpu", steps=300,
                                         options={"warm": False}))  # 300 of the run's 800: CI's 20 minutes
    assert report["method"] == "Direct-fsr" and np.isfinite(report["scores"]["m_psnr"])
    after, before = errors_toward(out / "run", with_hole(scene, masks), masks, painted / "images",
                                  stages["removed"] / "images")
    assert after < 0.75 * before  # measured at 300 steps: 44.0 against 81.8


def fsr_for_ft(stages) -> Path:
    inpainted = stages["work"] / "fsr-for-ft"
    if not inpainted.exists():
        run_inpaint(InpaintConfig(run=str(stages["run"]), inpainter="fsr", removed=str(stages["removed"]),
                                  holes=str(stages["holes"]), out=str(inpainted), dilate=1))
    return inpainted


def painted_for_ft(stages) -> Path:
    painted = stages["work"] / "painted-for-ft"
    return painted if painted.exists() else painted_fill(fsr_for_ft(stages), stages["holes"], painted)


@pytest.mark.parametrize("refs, perceptual", [(3, "l1"), (0, "lpips"), (3, "st-lpips")])
def test_finetune_freezes_the_original_gaussians_and_fills_the_hole(stages, tmp_path, monkeypatch, refs, perceptual):
    """FT(3) with the L1 perceptual term, FT(All) with LPIPS on tiny random weights made here, and FT(3) with
    ST-LPIPS from the weights `make setup` took from its wheel."""
    from test_metrics import save_tiny_lpips_weights

    from engine.complete.run import CompleteConfig, run_complete
    from engine.io.ply_io import load_ply

    inpainted = painted_for_ft(stages)
    backbone, heads = save_tiny_lpips_weights(tmp_path)
    monkeypatch.setenv("ST_LPIPS_WEIGHTS", str(setup_weight("alex_shift_tolerant.pth")))
    out = tmp_path / "ft"
    report = run_complete(CompleteConfig(run=str(stages["run"]), method="ft", inpainter="fsr", inpainted=str(inpainted),
                                         removed=str(stages["removed"]), holes=str(stages["holes"]), out=str(out),
                                         options={"refs": refs, "perceptual": perceptual}, steps=150, device="cpu",
                                         lpips_backbone=str(backbone), lpips_heads=str(heads)))
    names = {"l1": "FT-fsr(3)[l1]", "lpips": "FT-fsr(All)", "st-lpips": "FT-fsr(3)[st-lpips]"}
    assert report["method"] == names[perceptual]
    before = load_ply(stages["removed"] / "point_cloud.ply")
    after = load_ply(out / "run" / "point_cloud.ply")
    n = len(before["means"])
    assert len(after["means"]) > n  # new Gaussians in the hole
    for key, value in before.items():  # the published code's freeze fails; ours holds bit for bit
        assert torch.equal(after[key][:n], value), key
    # it fits its objective: inside the holes of the reference views, where the masked L1 pulls it, the render
    # moved toward the painted fill (mean absolute error 36.6, 24.5, 35.6 against the unfilled 84.4-85.9; with
    # fsr's own fill, which the unfilled render nearly is, 3.9 vs 4.3 on one seed)
    from engine.complete.finetune import reference_views
    from engine.io.masks import read_masks

    scene = load_run_scene(stages["run"])
    views = reference_views(read_masks(stages["holes"], scene.cameras), scene.train, refs)
    after, unfilled = errors_toward(out / "run", views, stages["holes"], inpainted / "images",
                                    stages["removed"] / "images")
    assert after < 0.75 * unfilled


def test_finetune_without_lpips_weights_says_how_to_go_on(stages, tmp_path, monkeypatch):
    from engine.complete.run import CompleteConfig, run_complete

    monkeypatch.delenv("LPIPS_BACKBONE", raising=False)
    monkeypatch.setenv("TORCH_HOME", str(tmp_path))
    with pytest.raises(InputError, match="--perceptual st-lpips or l1"):
        run_complete(CompleteConfig(run=str(stages["run"]), method="ft", inpainter="fsr",
                                    inpainted=str(fsr_for_ft(stages)),
                                    removed=str(stages["removed"]), holes=str(stages["holes"]),
                                    options={"perceptual": "lpips"}, out=str(tmp_path / "ft"), device="cpu"))


def test_recolmap_is_for_new_scenes_and_stops_cleanly_where_colmap_cannot_register(stages, tmp_path):
    """The tiny scene's 96x72 views hold too few SIFT features for COLMAP: a clear error, no scene folder left
    half-written (tests/complete/test_recolmap.py checks the poses where COLMAP succeeds)."""
    from engine.complete.run import CompleteConfig, run_complete

    inpainted = fsr_for_ft(stages)
    common = dict(run=str(stages["run"]), inpainter="fsr", inpainted=str(inpainted), removed=str(stages["removed"]),
                  device="cpu", options={"recolmap": True, "warm": False})
    with pytest.raises(InputError, match="--recolmap is not an option of --method ft"):
        run_complete(CompleteConfig(method="ft", out=str(tmp_path / "ft"), **common))
    with pytest.raises(InputError, match="without --recolmap"):
        run_complete(CompleteConfig(method="init", out=str(tmp_path / "init"), **common))
    assert not (tmp_path / "init" / "scene").exists()


def test_a_cancelled_finetune_resumes_with_complete_and_keeps_its_frozen_gaussians(stages, tmp_path):
    """SIGTERM during `complete --method ft` checkpoints and names `complete` again (or --resume);
    `train --resume` on that run refuses (it would drop the finetune's objective and frozen Gaussians);
    the same `complete` command finishes it with the removed scene's Gaussians unchanged bit for bit."""
    import json
    import signal

    from engine.complete.run import CompleteConfig, run_complete
    from engine.io.ply_io import load_ply

    out = tmp_path / "ft"
    args = ["--run", str(stages["run"]), "--method", "ft", "--inpainter", "fsr", "--inpainted", str(fsr_for_ft(stages)),
            "--removed", str(stages["removed"]), "--holes", str(stages["holes"]), "--out", str(out),
            "--perceptual", "l1", "--steps", "400", "--device", "cpu"]
    env = {**os.environ, "SPLATFILL_PROGRESS": "json"}
    proc = subprocess.Popen([sys.executable, "-m", "engine", "complete", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    for line in proc.stdout:
        if json.loads(line).get("stage") == "train" and json.loads(line).get("step", 0) > 0:
            proc.send_signal(signal.SIGTERM)
            break
    stderr = proc.communicate()[1]
    assert proc.returncode == 130, stderr
    assert "complete" in stderr.splitlines()[-1] and "--resume" in stderr.splitlines()[-1]
    train = subprocess.run([sys.executable, "-m", "engine", "train", "--scene", str(out / "scene"), "--out",
                            str(out / "run"), "--resume"], capture_output=True, text=True, env=env)
    assert train.returncode == 2 and "complete" in train.stderr and "--resume" in train.stderr
    report = run_complete(CompleteConfig(run=str(stages["run"]), method="ft", inpainter="fsr",
                                         inpainted=str(fsr_for_ft(stages)),
                                         removed=str(stages["removed"]), holes=str(stages["holes"]), out=str(out),
                                         options={"perceptual": "l1"}, steps=400, device="cpu",
                                         turntable=False))  # the same command again, no --resume
    assert report["method"] == "FT-fsr(3)[l1]"
    before, after = load_ply(stages["removed"] / "point_cloud.ply"), load_ply(out / "run" / "point_cloud.ply")
    n = len(before["means"])
    assert len(after["means"]) > n
    for key, value in before.items():
        assert torch.equal(after[key][:n], value), key


def test_a_completion_stopped_before_training_runs_again_with_the_same_command(stages, tmp_path):
    """Stopped before its first step (its run/ made, never configured; a scene write cut short): the same
    command starts it again, nobody deletes anything by hand. A finished one, and a folder that is not a
    completion's, are refused with one line, and the latter is left as it was."""
    from engine.complete.run import CompleteConfig, run_complete

    out = tmp_path / "init"
    (out / "run").mkdir(parents=True)
    (out / ".scene.tmp-999").mkdir()
    config = CompleteConfig(run=str(stages["run"]), method="init", inpainter="fsr",
                            inpainted=str(fsr_for_ft(stages)), removed=str(stages["removed"]), out=str(out), steps=30,
                            device="cpu", options={"warm": False}, turntable=False)
    report = run_complete(config)
    assert (out / "scores.json").is_file() and report["gaussians"] > 0
    assert not list(out.glob(".*.tmp-*"))
    with pytest.raises(InputError, match="is finished"):
        run_complete(config)
    other = tmp_path / "mine"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match="already exists"):
        run_complete(CompleteConfig(**{**config.__dict__, "out": str(other)}))
    assert [p.name for p in other.iterdir()] == ["notes.txt"]


def test_a_warm_init_trains_only_what_renders_into_the_hole_and_leaves_the_rest_as_removal_left_it(stages, tmp_path):
    """Init-fsr[warm], the default: the removed scene's Gaussians that render into the hole and new ones on its
    inpainted surface are trained, for a tenth of the base run's steps (100 of 800), with the base run's
    classifier; every other Gaussian is fixed, bit for bit, so outside the holes (grown by the inpainting's
    dilation) every view renders as the removed scene does; inside them the renders moved toward the fill."""
    import dataclasses

    import torch

    from engine.complete.hole_region import hole_bound
    from engine.complete.run import CompleteConfig, _job, run_complete
    from engine.complete.warm_start import GRAFT_RING_PX, _hole_views, warm_setup
    from engine.io.ply_io import load_ply
    from engine.render.render_views import render_pictures
    from engine.train.trained_run import load_run

    inpainted = fsr_for_ft(stages)
    common = dict(run=str(stages["run"]), inpainter="fsr", inpainted=str(inpainted), removed=str(stages["removed"]),
                  device="cpu")
    job = _job(CompleteConfig(method="init", out=str(tmp_path / "setup"), **common))  # the default
    settings, plugins = warm_setup(job, dataclasses.replace(job.original.config))
    removed = load_ply(stages["removed"] / "point_cloud.ply")
    fixed, start = plugins["fixed"], plugins["start"]
    assert job.options["warm"] and settings.steps == 100 and settings.sh_degree_interval == 1
    assert 0 < len(start["means"]) and 0.5 * len(removed["means"]) < len(fixed["means"]) < len(removed["means"])
    assert torch.equal(plugins["classifier"].weight, job.original.classifier.weight)

    out = tmp_path / "warm"
    report = run_complete(CompleteConfig(method="init", out=str(out), options={"warm": True}, **common))
    assert report["method"] == "Init-fsr[warm]" and np.isfinite(report["scores"]["m_psnr"])
    trained = load_run(out / "run")
    assert trained.config.steps == 100
    n = len(fixed["means"])
    assert all(torch.equal(trained.gaussians[k][:n], fixed[k]) for k in ("means", "scales", "opacities", "sh0"))
    # what trained stays in the hole in every view, the test views no step drew included (on a tiny run of training
    # seed 1, 6 of 351 trained Gaussians had left it and were dropped: warm_start.confine)
    holes, depths = _hole_views(job, removed)
    ringed = {i: dilate(hole, GRAFT_RING_PX) for i, hole in holes.items()}
    assert report["kept_to_hole"]["fixed"] == n
    assert hole_bound(trained.gaussians["means"][n:].numpy(), job.original.scene, ringed, depths).all()
    scene = trained.scene
    # the kept score comes with where each test view changed (engine.complete.scoring.kept_changes)
    assert set(report["kept_views"]) == {scene.cameras[i].name for i in scene.test}
    assert all(0 <= v["changed_share"] <= 1 for v in report["kept_views"].values())
    grown = read_masks_grown(stages["holes"], scene.cameras, inpainted)
    for camera, picture in zip(scene.cameras, render_pictures(trained.gaussians, scene.cameras, trained.sh_degree,
                                                              "cpu"), strict=True):
        outside = ~dilate(grown[camera.name], 2)
        before = read_png(stages["removed"] / "images" / camera.name).astype(float)
        # measured: 52.9-66.1 dB a view, and 47.8 in one view of one of the fixture's trainings (they differ with
        # the threads a test worker has); with every Gaussian trained (the old warm start) the worst view 39.8
        assert psnr_where(picture.rgb.astype(float), before, outside) > 45, camera.name
    after, before = errors_toward(out / "run", with_hole(scene, stages["holes"]), stages["holes"],
                                  inpainted / "images", stages["removed"] / "images")
    assert after < before
    with pytest.raises(InputError, match="add --no-warm"):
        run_complete(CompleteConfig(method="init", out=str(tmp_path / "both"), options={"warm": True, "recolmap": True},
                                    **common))


def test_a_scratch_init_keeps_the_removed_scene_outside_the_hole_and_its_own_scene_inside(stages, tmp_path):
    """Init-fsr from scratch (--no-warm), 200 steps: the new scene is grafted into the removed one at the hole, so
    outside the holes every view renders as the removed scene does, as the warm start does; --no-keep-rest keeps
    the paper's whole new scene (Init-fsr[whole]), which does not."""
    from engine.complete.run import CompleteConfig, run_complete
    from engine.render.render_views import render_pictures
    from engine.train.trained_run import load_run

    inpainted = fsr_for_ft(stages)
    common = dict(run=str(stages["run"]), method="init", inpainter="fsr", inpainted=str(inpainted),
                  removed=str(stages["removed"]), device="cpu", steps=200, turntable=False)
    worst = {}
    for keep in (True, False):
        out = tmp_path / f"keep{keep}"
        report = run_complete(CompleteConfig(out=str(out), options={"warm": False, "keep_rest": keep}, **common))
        assert report["method"] == ("Init-fsr" if keep else "Init-fsr[whole]")
        assert (report["kept_to_hole"] is not None) == keep
        trained = load_run(out / "run")
        scene = trained.scene
        grown = read_masks_grown(stages["holes"], scene.cameras, inpainted)
        worst[keep] = min(
            psnr_where(picture.rgb.astype(float), read_png(stages["removed"] / "images" / camera.name).astype(float),
                       ~dilate(grown[camera.name], 2))
            for camera, picture in zip(scene.cameras, render_pictures(trained.gaussians, scene.cameras,
                                                                      trained.sh_degree, "cpu"), strict=True))
    # measured on tiny runs of training seeds 0-4, worst view (mean): grafted 38.2 (47.4) / 38.6 (48.9) / 43.1 (48.2) /
    # 43.4 (47.8) / 42.6 (48.5); whole 16.6-20.0. With the removed scene's wide Gaussians centred in the hole dropped
    # (hole_region.changeable keeps them): 35.9 (41.1) on seed 0, 27.5 on seed 2
    assert worst[True] > 30 > worst[False], worst


@pytest.mark.parametrize("method", ["reference", "ft"])
def test_a_completion_with_no_hole_in_any_view_finishes_with_the_removed_scene(stages, tmp_path, method):
    """Hole masks empty in every view (every view saw behind the object): Ref[warm], the default, and FT train no
    step and their scene is the removed one, bit for bit, rendered as removal rendered it, with the report saying
    why, instead of the error the README path's test met on CI."""
    import shutil

    import torch

    from engine.complete.run import CompleteConfig, run_complete
    from engine.io.ply_io import load_ply
    from engine.train.trained_run import load_run

    empty = tmp_path / "holes"
    shutil.copytree(stages["holes"], empty)
    for mask in empty.glob("*.png"):
        write_png(mask, np.zeros_like(read_png(mask, kind="mask")))
    out = tmp_path / method
    report = run_complete(CompleteConfig(run=str(stages["run"]), method=method, inpainter="fsr",
                                         inpainted=str(fsr_for_ft(stages)), removed=str(stages["removed"]),
                                         holes=str(empty), out=str(out), device="cpu", turntable=False,
                                         options={"perceptual": "l1"} if method == "ft" else {}))
    assert "no training view has a hole" in report["nothing_to_train"], report.get("nothing_to_train")
    trained, removed = load_run(out / "run"), load_ply(stages["removed"] / "point_cloud.ply")
    assert trained.config.steps == 0 and trained.sh_degree == load_run(stages["run"]).sh_degree
    assert all(torch.equal(trained.gaussians[k], removed[k].float()) for k in ("means", "scales", "sh0", "shN"))
    for render in (out / "renders").iterdir():
        assert np.array_equal(read_png(render), read_png(stages["removed"] / "images" / render.name)), render.name


def read_masks_grown(holes: Path, cameras, inpainted: Path) -> dict[str, np.ndarray]:
    """Each view's hole as the inpainting grew it (its config's dilation)."""
    from engine.formats.layout import InpaintedLayout
    from engine.inpaint.run import inpainted_dilation

    pixels = inpainted_dilation(InpaintedLayout(inpainted))
    return {c.name: dilate(read_png(holes / c.name, kind="mask") > 0, pixels) for c in cameras}


def psnr_where(a: np.ndarray, b: np.ndarray, keep: np.ndarray) -> float:
    mse = float((((a - b) / 255.0) ** 2)[keep].mean())
    return 10 * np.log10(1 / max(mse, 1e-12))


def test_a_later_reference_view_seeds_only_where_earlier_ones_left_space():
    """FT(All)'s views see the same hole: the second view's points on the same surface add nothing, its
    points past the first view's reach all stay, and the first view keeps every point of its own grid."""
    from engine.complete.finetune import first_seen

    u, v = np.meshgrid(np.arange(20) * 0.02, np.arange(20) * 0.02)
    first = np.stack([u.ravel(), v.ravel(), np.zeros(u.size)], 1)  # a 20x20 grid, 0.02 apart
    again = first[:100] + 0.003  # the same surface seen again, a fraction of a cell off
    beyond = first[:50] + np.array([1.0, 0.0, 0.0])  # surface the first view did not reach
    keep = first_seen([first, np.concatenate([again, beyond])], spacing=0.02)
    assert keep[0].all()
    assert keep[1][100:].all() and keep[1][:100].sum() <= 10  # grid-cell borders let a few through
