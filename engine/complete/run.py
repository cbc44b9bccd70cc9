"""Stage 5: complete the scene from the inpainted views, and score the result on the test views.

`init` (the paper's Init-<inpainter>): train a new scene from scratch on the inpainted images with the
original cameras and sparse points (COLMAP is not re-run), with the training run's own settings. The
training scene is a folder of its own, RUN/complete/<Name>/scene (written atomically): sparse/ and
split.json as they were, images/ the training views: the inpainted render inside the removed object's
region (grown by the inpainting's dilation and 2 px), the input image outside it (test views: the ground
truth when the scene has it, so the
training run's own test PSNR means something; they are never trained on), masks/ with the removed object's
id turned into background, and gt/ and holes/ for scoring. Then RUN/complete/<Name>/run is an ordinary
training run (resumable like any other), renders/ holds its test views, and scores.json, written last
and atomically, holds the
metrics of engine.metrics.scores on the test views beside the same metrics for the removed-but-unfilled scene.

`direct` (the paper's Init-NanoBanana, made general): the same training on images whose whole object
region was inpainted in the input images (`inpaint --source input`), with no removal step in between.

`--recolmap` (init and direct; the paper's COLMAP ablation): the training scene's poses and sparse points
are re-estimated by COLMAP from its training images (engine.complete.recolmap), and the report gives how many views
registered and their pose error against the original cameras.

`ft` (FT-<inpainter>(3) / FT-<inpainter>(All)): finetune the removed scene into the hole from the same
training scene, the removed Gaussians frozen (engine.complete.finetune).

Method names follow the paper: Init-<inpainter>, Direct-<inpainter>, FT-<inpainter>(3|All); an FT run with
the L1 perceptual term instead of LPIPS is named FT-<inpainter>(3)[l1].
"""

from __future__ import annotations

import dataclasses
import json
import shutil
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from engine.base.device import pick_device
from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir, check_new_output
from engine.base.progress import emit
from engine.complete.finetune import finetune_setup
from engine.complete.method_names import METHODS, method_name
from engine.complete.recolmap import rerun_colmap
from engine.inpaint.run import inpainted_dilation
from engine.io.image_io import read_png, write_png
from engine.io.masks import read_masks
from engine.io.scene import Scene
from engine.metrics.scores import ScoreConfig, Scorer, Scores
from engine.render.render_views import render_pictures
from engine.train.run import train
from engine.train.trained_run import load_run


@dataclass
class CompleteConfig:
    run: str = ""
    method: str = "init"
    inpainter: str = "fsr"
    refs: int = 3  # ft: reference views, the training views with the largest holes (0 = all with a hole)
    perceptual: str = "lpips"  # ft: the term on non-reference views (lpips | l1)
    inpainted: str = ""  # default RUN/inpainted/<inpainter>
    removed: str = ""  # default RUN/removed (its removal.json names the object; its renders are the baseline)
    holes: str = ""  # ft: default RUN/holes
    out: str = ""  # default RUN/complete/<Name>
    steps: int = 0  # 0: the training run's own (init, direct) or a tenth of it (ft)
    seed: int = 0
    device: str = "auto"
    lpips_backbone: str = ""  # see engine.metrics.scores.ScoreConfig
    lpips_heads: str = ""
    fid_weights: str = ""
    recolmap: bool = False  # init, direct: re-estimate poses and points with pycolmap (engine.complete.recolmap)


def run_complete(config: CompleteConfig) -> dict:
    if config.method not in METHODS:
        raise InputError(f"unknown method {config.method!r}; choose from {', '.join(METHODS)}")
    original = load_run(config.run)
    root = original.root
    removed = Path(config.removed) if config.removed else root / "removed"
    folder = f"direct-{config.inpainter}" if config.method == "direct" else config.inpainter
    inpainted = Path(config.inpainted) if config.inpainted else root / "inpainted" / folder
    source = " --source input" if config.method == "direct" else ""
    for path, command in ((removed, "remove"), (inpainted, f"inpaint --inpainter {config.inpainter}{source}")):
        if not path.is_dir():
            raise InputError(f"{path} missing: run `python -m engine {command} --run {root}` first")
    if config.recolmap and config.method == "ft":
        raise InputError("--recolmap re-estimates the cameras of a new scene: use it with --method init or direct")
    target = json.loads((removed / "removal.json").read_text()).get("object")
    name = method_name(config.method, config.inpainter, config.refs, config.perceptual, config.recolmap)
    out = Path(config.out) if config.out else root / "complete" / name
    check_new_output(out)
    start = time.perf_counter()
    keep = _object_regions(original.scene, removed, inpainted) if config.method == "init" else None
    colmap = None
    with atomic_output_dir(out / "scene") as tmp:
        _training_scene(original.scene, inpainted, target and target["id"], tmp, keep)
        if config.recolmap:
            train_names = [original.scene.names[i] for i in original.scene.train]
            colmap = rerun_colmap(tmp, train_names, tmp / "colmap")
    settings = dataclasses.replace(original.config, scene=str(out / "scene"), out=str(out / "run"), seed=config.seed,
                                   device=config.device, steps=config.steps or original.config.steps)
    plugins = None
    if config.method == "ft":
        holes = Path(config.holes) if config.holes else root / "holes"
        settings, plugins = finetune_setup(
            settings, original, removed, inpainted, holes, config.refs, config.perceptual,
            config.steps or max(original.config.steps // 10, 100), config.seed, pick_device(config.device),
            (config.lpips_backbone, config.lpips_heads))
    metrics = train(settings, plugins=plugins)
    seconds = time.perf_counter() - start
    scorer = Scorer(_score_config(config))
    scores = score_run(out / "run", scorer, renders=out / "renders")
    baseline = score_removed(original.scene, removed, scorer)
    report = {"method": name, "config": dataclasses.asdict(config), "seconds": round(seconds, 1),
              "gaussians": metrics["gaussians"], "scores": scores.values, "unavailable": scores.unavailable,
              "removed_scores": baseline.values, "recolmap": colmap}
    partial = out / ".scores.json.tmp"
    partial.write_text(json.dumps(report, indent=1))
    partial.replace(out / "scores.json")  # written last: a folder with scores.json is a finished cell
    emit("done", stage="complete", method=name, out=str(out), m_psnr=report["scores"]["m_psnr"])
    return report


def _score_config(config: CompleteConfig) -> ScoreConfig:
    device = str(pick_device(config.device))
    return ScoreConfig(lpips_backbone=config.lpips_backbone, lpips_heads=config.lpips_heads,
                       fid_weights=config.fid_weights, device=device)


def _object_regions(scene: Scene, removed: Path, inpainted: Path, margin: int = 2) -> dict[int, np.ndarray]:
    """Per view, where the inpainted render replaces the input image: the removed object's region (removal's
    masks) grown by the inpainting's dilation and `margin` px. Elsewhere the input image is the truth, and
    a render of the removed scene is only a copy of it with the model's errors, which a new scene trained on
    renders alone would learn. (Measured on a tiny run, test-view PSNR: 16.0 dB on renders alone, 16.4 with
    the input images, against 20.0 for the unfilled scene; most of that gap is the tiny runs' seed noise.)"""
    return read_masks(removed / "masks", scene.cameras, inpainted_dilation(inpainted) + margin)


def _training_scene(scene: Scene, inpainted: Path, target_id: int | None, out: Path,
                    keep: dict[int, np.ndarray] | None = None) -> Path:
    """The scene folder a completion run trains on (see the module docstring); with `keep`, the training
    images are the inpainted ones only inside those regions and the input images elsewhere."""
    shutil.copytree(scene.root / "sparse", out / "sparse")
    for name in ("split.json", "scene.json"):
        if (scene.root / name).is_file():
            shutil.copy2(scene.root / name, out / name)
    for folder in ("gt", "holes"):
        if (scene.root / folder).is_dir():
            shutil.copytree(scene.root / folder, out / folder)
    for i, camera in enumerate(scene.cameras):
        if i in scene.test:
            image = scene.gt_images.get(i, scene.images[i])
        else:
            image = read_png(inpainted / "images" / camera.name)
            if keep is not None:
                image = np.where(keep[i][..., None], image, scene.images[i])
        write_png(out / "images" / camera.name, image)
    if scene.masks is not None:
        for camera, mask in zip(scene.cameras, scene.masks, strict=True):
            write_png(out / "masks" / Path(camera.name).with_suffix(".png"),
                      np.where(mask == target_id, 0, mask).astype(np.uint8))
        objects = [dataclasses.asdict(o) for o in scene.objects if o.id != target_id]
        (out / "masks" / "objects.json").write_text(json.dumps(objects, indent=1))
    return out


def _test_sets(scene: Scene) -> tuple[list[int], list[np.ndarray], list[np.ndarray]]:
    views = [i for i in scene.test if i in scene.gt_images and i in scene.holes]
    if not views:
        raise InputError(f"{scene.root} has no test views with gt/ and holes/: scores need a generated scene")
    return views, [scene.gt_images[i] for i in views], [scene.holes[i] for i in views]


def score_run(run_dir: Path, scorer: Scorer, renders: Path | None = None) -> Scores:
    """Scores of a trained run's test renders against its scene's gt/, masked by holes/; the renders are
    saved under `renders` when given (the benchmark's side-by-side pictures read them)."""
    run = load_run(run_dir)
    views, truths, holes = _test_sets(run.scene)
    pictures = [p.rgb for p in render_pictures(run.gaussians, [run.scene.cameras[i] for i in views],
                                               run.sh_degree, pick_device(scorer.config.device))]
    if renders is not None:
        for i, rgb in zip(views, pictures, strict=True):
            write_png(renders / run.scene.cameras[i].name, rgb)
    return scorer.score(pictures, truths, holes)


def score_removed(scene: Scene, removed: Path, scorer: Scorer) -> Scores:
    """The same scores for the removed-but-unfilled scene's renders (the floor every method must beat)."""
    views, truths, holes = _test_sets(scene)
    return scorer.score([read_png(removed / "images" / scene.cameras[i].name) for i in views], truths, holes)
