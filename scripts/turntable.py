"""A before/after turntable around a removed object, rendered by the engine's rasterizer.

    blender -b -P scripts/turntable.py -- --run RUN --removed RUN/removed [--after PLY] [--frames 48] --out DIR
        [--keep-frames]
    blender -b scene.blend -P scripts/turntable.py -- --run RUN --removed ... --camera Camera --out DIR
    python scripts/turntable.py --run RUN --removed RUN/removed --out DIR      # the bpy module works too

`python -m engine turntable` does the work (engine/pictures/turntable.py: the orbit around the removed object,
both renders, the labelled side-by-side frames and DIR/turntable.mp4, H.264, decoded again and counted before it
is kept); the add-on's Turntable operator runs the same command. `--camera` takes a Blender camera's path over
the scene's frame range instead of the orbit (addon/camera_path.py), which needs Blender or the bpy module.
`--keep-frames` keeps the side-by-side PNGs (DIR/frames/) and both renders (DIR/before/, DIR/after/).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from blender_entry import add_repo_to_path, script_args  # noqa: E402

add_repo_to_path()
from addon.engine_call import EngineError, run_engine  # noqa: E402
from addon.formats import InputError  # noqa: E402


def blender_cameras(camera_name: str, folder: Path) -> Path:
    """The named camera's path, written as a cameras.json in `folder` for the engine to follow."""
    import bpy

    from addon.camera_path import camera_path

    path = folder / "cameras.json"
    path.write_text(json.dumps(camera_path(bpy.data.objects.get(camera_name), bpy.context.scene), indent=1))
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", required=True, help="the original training run")
    parser.add_argument("--removed", required=True, help="the removal's output folder (its removal.json)")
    parser.add_argument("--after", default="", help=".ply shown as 'after' (default: the removed scene)")
    parser.add_argument("--out", required=True, help="new folder for cameras.json and turntable.mp4")
    parser.add_argument("--frames", type=int, default=48)
    parser.add_argument("--camera", default="", help="a Blender camera of the open .blend, over its frame range")
    parser.add_argument("--fps", type=int, default=24)
    parser.add_argument("--keep-frames", action="store_true", help="keep frames/, before/ and after/ beside the MP4")
    parser.add_argument("--device", default="auto")
    args = parser.parse_args(script_args(argv))
    command = ["turntable", "--run", args.run, "--removed", args.removed, "--out", args.out, "--frames",
               str(args.frames), "--fps", str(args.fps), "--device", args.device,
               *(["--after", args.after] if args.after else []), *(["--keep-frames"] if args.keep_frames else [])]
    try:
        with tempfile.TemporaryDirectory() as folder:
            if args.camera:
                command += ["--cameras", str(blender_cameras(args.camera, Path(folder)))]
            records = run_engine(command)
    except (EngineError, InputError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    video = next(r["out"] for r in records if r.get("event") == "done" and r.get("stage") == "turntable")
    print(f"video: {video}" + (f"  frames: {Path(args.out) / 'frames'}" if args.keep_frames else ""), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
