"""One benchmark cell and the stages it shares with the other cells of its scene and seed (benchmarks/matrix.py).

Apart from the matrix and its tables because two schedulers run them: one after the other in the benchmark's own
process, or as Ray tasks in worker processes (benchmarks/matrix_ray.py), which import this module and nothing of
the tables. Every stage skips what is on disk, so either scheduler resumes what the other left.
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import shutil
import time
from pathlib import Path

from addon.engine_call import EngineError, run_engine
from engine.complete.registry import CompletionMethod, benchmark_cells, get, resolve_options
from engine.formats.checks import png_size
from engine.formats.layout import RunLayout, SceneLayout
from engine.formats.protocol import scene_role

BENCHWIDE_OPTIONS = ("perceptual",)  # options the benchmark sets, when given, for every method that has them


class MissingTime(RuntimeError):
    """A stage is on disk but no process of this benchmark timed it: its cells' run times would undercount."""


class Stages:
    """The shared stages of one scene and seed, each run once and timed. Every process a stage takes writes its
    own record under times/ (no file is read, changed and written back, so processes of other cells running at
    once lose nothing); a stage's time is the sum of its processes (a stage that failed and ran again counts
    both), each timed around the engine's whole process, its start and loading included."""

    def __init__(self, scene: Path, seed: int, work: Path, args: argparse.Namespace) -> None:
        self.scene, self.seed, self.args = scene, seed, args
        self.root = work / scene.name / f"seed{seed}"
        self.run = RunLayout(self.root / "run")
        self.times_dir = self.root / "times"

    def stage(self, key: str, done: Path, args: list[str]) -> None:
        if done.exists():
            return
        self.timed(key, args)

    def timed(self, key: str, args: list[str]) -> None:
        """Run the engine with `args`, recording the process's seconds under `key` whether it succeeds or not."""
        start, ok = time.perf_counter(), False
        try:
            run_engine(args)
            ok = True
        finally:
            record = {"stage": key, "seconds": round(time.perf_counter() - start, 2), "ok": ok}
            self.times_dir.mkdir(parents=True, exist_ok=True)
            name = f"{key}.{os.getpid()}.{time.time_ns()}.json"
            partial = self.times_dir / f".{name}.tmp"
            partial.write_text(json.dumps(record))
            partial.replace(self.times_dir / name)

    def seconds(self, key: str) -> float:
        """Every process's seconds of stage `key`, summed; a stage with none recorded is an error naming it."""
        records = [json.loads(p.read_text()) for p in sorted(self.times_dir.glob(f"{glob.escape(key)}.*.json"))]
        if not records:
            raise MissingTime(f"stage {key!r} of {self.root} is on disk but was never timed: delete its folder "
                              "and run the benchmark again")
        return round(sum(r["seconds"] for r in records), 2)

    @property
    def times(self) -> dict[str, float]:
        """Each timed stage's seconds, summed over its processes."""
        keys = sorted({p.name.split(".")[0] for p in self.times_dir.glob("*.json")}) if self.times_dir.is_dir() else []
        return {k: self.seconds(k) for k in keys}

    def train(self) -> None:
        a = self.args
        resume = ["--resume"] if self.run.config_json.is_file() else []
        options = ["--preset", a.preset, "--device", a.device]
        options += ["--max-gaussians", str(a.max_gaussians)] if a.max_gaussians is not None else []
        options += ["--steps", str(a.steps)] if a.steps else []
        run = str(self.run.root)
        self.stage("train", self.run.point_cloud, ["train", "--scene", str(self.scene), "--out", run, "--seed",
                                                   str(self.seed), *options, *resume])

    def base(self) -> None:
        """Train and remove the target: what every cell of this scene and seed shares."""
        self.train()
        self.stage("remove", self.run.removed.root, ["remove", "--run", str(self.run.root), "--object",
                                                     _target(self.scene), "--device", self.args.device])

    def holes(self) -> None:
        """The base stages, then the removed scene's hole masks: what the cells that inpaint its renders need.
        The direct baseline paints the input images and does not wait for them (under Ray its inpainting, the
        matrix's longest, starts one stage earlier)."""
        self.base()
        self.stage("holes", self.run.holes.root, ["holes", "--run", str(self.run.root)])

    def inpaint(self, inpainter: str, source: str) -> None:
        dilate = [] if self.args.dilate is None else ["--dilate", str(self.args.dilate)]
        self.stage(_inpaint_key(inpainter, source), self.run.inpainted(inpainter, source).root,
                   ["inpaint", "--run", str(self.run.root), "--inpainter", inpainter, "--source", source, *dilate])

    def prepare(self, inpainter: str, source: str) -> None:
        self.holes()  # Direct too: a warm completion trains only what renders into the hole (hole_region)
        self.inpaint(inpainter, source)

    def needs(self, source: str, inpainter: str) -> dict[str, float]:
        """Seconds of each shared stage a cell depends on: the base run, the removal (Direct paints the input
        images, but its object regions come from the removal), the hole masks (what a warm completion may train,
        and where the removed renders are inpainted) and its inpainting."""
        keys = ("train", "remove", "holes", _inpaint_key(inpainter, source))
        return {k: self.seconds(k) for k in keys}


def _inpaint_key(inpainter: str, source: str) -> str:
    return f"inpaint-{inpainter}" if source == "removed" else f"inpaint-direct-{inpainter}"


def _target(scene: Path) -> str:
    path = SceneLayout(scene).objects_json
    targets = [o["name"] for o in json.loads(path.read_text()) if o.get("target")]
    if not targets:
        raise EngineError(f"{path} marks no target object")
    return targets[0]


def _option_flags(options: dict) -> list[str]:
    flags = []
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        flags += ([flag if value else f"--no-{name.replace('_', '-')}"] if isinstance(value, bool)
                  else [flag, str(value)])
    return flags


def cell_method(method: str, args: argparse.Namespace) -> tuple[CompletionMethod, dict, int]:
    """A benchmark cell's completion method, its options (the cell's, the benchmark-wide ones, the rest at their
    defaults) and its steps: --short-steps for those that continue from the base run's scene (FT, the warm new
    scenes), --complete-steps for those that train from scratch; 0 leaves the engine's default."""
    spec = benchmark_cells()[method]
    kind = get(spec.method)
    wide = {k: getattr(args, k) for k in BENCHWIDE_OPTIONS
            if k in {o.name for o in kind.options} and getattr(args, k, None) is not None}
    options = resolve_options(kind, {**spec.options, **wide})
    return kind, options, args.short_steps if kind.short(options) else args.complete_steps


def run_cell(stages: Stages, method: str, inpainter: str, args: argparse.Namespace, failed: str = "") -> dict:
    """One cell: its shared stages where not done (`failed`: the reason they failed elsewhere), then
    `engine complete`, unless its scores.json is there already."""
    kind, options, steps = cell_method(method, args)
    name = kind.title(inpainter, options)
    cell = {"scene": stages.scene.name, "seed": stages.seed, "inpainter": inpainter, "method": name,
            "role": scene_role(stages.scene)}
    out = stages.run.complete(name)
    if args.report_only and not out.scores_json.is_file():
        return {**cell, "status": "not run", "reason": "not finished when the report was written (--report-only)"}
    if failed and not out.scores_json.is_file():
        return {**cell, "status": "failed", "reason": failed}
    try:
        if not out.scores_json.is_file():
            stages.prepare(inpainter, kind.source)
            shutil.rmtree(out.root, ignore_errors=True)  # an interrupted cell starts again
            flags = ["--method", kind.name, "--inpainter", inpainter, "--seed", str(stages.seed), "--device",
                     args.device, "--no-turntable", *_option_flags(options)]  # a cell's pictures are its renders
            flags += ["--steps", str(steps)] if steps else []
            stages.timed(f"complete-{name}", ["complete", "--run", str(stages.run.root), "--out", str(out.root),
                                              *flags])
        report = json.loads(out.scores_json.read_text())
        needs, complete = stages.needs(kind.source, inpainter), stages.seconds(f"complete-{name}")
    except (EngineError, MissingTime) as exc:
        return {**cell, "status": "failed", "reason": str(exc)}
    return {**cell, "status": "done", **report["scores"], "gaussians": report["gaussians"],
            "settings": cell_settings(stages, inpainter, kind.source, report),
            "scene_dir": str(stages.scene), "renders": str(out.renders),
            "commit": (report.get("versions") or {}).get("commit"), **hole_ious(stages.run, inpainter, kind.source),
            "seconds": round(sum(needs.values()) + complete, 1), "stages": needs,
            "complete_seconds": complete,  # the completion's processes, their start and loading included
            "removed_scores": report["removed_scores"], "oracle_scores": report.get("oracle_scores"),
            "unavailable": report["unavailable"],
            "phases": report.get("phases", {}) | {"process": complete}}


BASE_KEYS = ("preset", "steps", "max_gaussians", "resolution", "sh_degree", "seed")


def hole_ious(run: RunLayout, inpainter: str, source: str) -> dict:
    """The hole masks against the scene's true holes, over every view that has them: as `holes` wrote them
    (`hole_iou`), their unseen part alone (`unseen_iou`, which leaves out what the masks add for see-through
    views), and as the cell's inpainting filled them, its dilation included (mean and worst view); and the
    removal's PSNR outside the true hole over every view (mean and worst)."""
    holes, removal = _json(run.holes.report), _json(run.removed.report)
    used = _json(run.inpainted(inpainter, source).config_json).get("hole_iou_as_inpainted") or {}
    outside = removal.get("psnr_outside_hole_every_view") or {}
    return {"hole_iou": holes.get("mean_iou_vs_truth"), "unseen_iou": holes.get("mean_unseen_iou_vs_truth"),
            "hole_iou_inpainted": used.get("mean"), "hole_iou_inpainted_worst": used.get("worst"),
            "removal_psnr_outside": outside.get("mean"), "removal_psnr_outside_worst": outside.get("worst")}


def _json(path: Path) -> dict:
    return json.loads(path.read_text()) if path.is_file() else {}


def cell_settings(stages: Stages, inpainter: str, source: str, report: dict) -> dict:
    """What a finished cell ran with, kept in its record: the base run's settings, GPU and versions (from its
    config.json and metrics.json), the scene's views and image size, the removal's, hole masks' and inpainting's
    settings and the completion's own."""
    config, metrics = _json(stages.run.config_json), _json(stages.run.metrics_json)
    split = _json(SceneLayout(stages.scene).split_json)
    images = sorted(p for p in SceneLayout(stages.scene).images.iterdir() if p.is_file())
    pngs = [p for p in images if p.suffix.lower() == ".png"]
    inpainted = _json(stages.run.inpainted(inpainter, source).config_json).get("config", {})
    removal, holes = _json(stages.run.removed.report), _json(stages.run.holes.report)
    return {"base": {k: config.get(k) for k in BASE_KEYS} | {"gaussians": metrics.get("gaussians"),
                                                           "train_seconds": metrics.get("train_seconds")},
            "scene": {"views": len(images), "train": len(split.get("train", [])), "test": len(split.get("test", [])),
                      "size": list(png_size(pngs[0]) or ()) if pngs else None},
            "remove": removal.get("config"), "holes": holes.get("config") if source == "removed" else None,
            "inpaint": {k: v for k, v in inpainted.items() if k not in ("run", "removed", "holes", "out")},
            "complete": report.get("config", {}), "gpu": metrics.get("gpu"), "versions": metrics.get("versions")}

