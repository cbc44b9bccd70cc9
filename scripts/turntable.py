"""A before/after turntable around a removed object, rendered by the engine's rasterizer.

    blender -b -P scripts/turntable.py -- --run RUN --removed RUN/removed [--after PLY] [--frames 48] --out DIR
        [--keep-frames]
    blender -b scene.blend -P scripts/turntable.py -- --run RUN --removed ... --camera Camera --out DIR
    python scripts/turntable.py --run RUN --removed RUN/removed --out DIR      # the bpy module works too

The orbit circles the removed object's centre (the mean of its Gaussians in the original run) at the
median distance and height of the scene's own cameras, around their mean up direction, with the first
camera's intrinsics; `--camera` takes a Blender camera's path over the scene's frame range instead. Both
scenes (before: RUN/point_cloud.ply; after: the removed scene, or any .ply such as a completed run's) are
rendered from the same cameras.json by `python -m engine render` (3DGS quality, which Blender's own
renderers cannot give a splat), put side by side with labels (`python -m engine compare --per-view`),
and written as DIR/turntable.mp4 (H.264, by `python -m engine video` with the FFmpeg the engine's
imageio-ffmpeg wheel ships; decoded again and its frames counted before it is kept). `--keep-frames` keeps the
side-by-side PNGs (DIR/frames/) and both renders (DIR/before/, DIR/after/); by default they go once the MP4 is
written.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from blender_entry import add_repo_to_path, script_args  # noqa: E402

add_repo_to_path()
from addon.engine_call import EngineError, run_engine  # noqa: E402
from addon.splat_ply import read_splats  # noqa: E402
from engine.formats import cameras as camera_formats  # noqa: E402
from engine.formats.layout import RemovedLayout, RunLayout  # noqa: E402


def object_centre(run: RunLayout, removed: RemovedLayout) -> np.ndarray:
    """Where the removed object was: the mean of its Gaussians in the original run (or its box's centre)."""
    report = json.loads(removed.report.read_text())
    if report.get("object") is None:
        box = np.array(report["config"]["box"], dtype=float)
        return (box[:3] + box[3:]) / 2
    splats = read_splats(run.point_cloud)
    mine = splats.groups == report["object"]["id"]
    if not mine.any():
        raise EngineError(f"no Gaussian of {report['object']['name']} in {run.point_cloud}")
    return splats.positions[mine].mean(0).astype(np.float64)


def orbit(records: list[dict], centre: np.ndarray, frames: int) -> list[dict]:
    """`frames` cameras on a circle around `centre`, at the scene cameras' median distance and height."""
    R = np.array([r["R"] for r in records])
    centres = np.array([camera_formats.camera_to_world(r["R"], r["t"])[:3, 3] for r in records])
    up = -R[:, 1, :].mean(0)  # a camera's -y axis (OpenCV) points up in the world
    up /= np.linalg.norm(up)
    offsets = centres - centre
    height = float(np.median(offsets @ up))
    flat = offsets - np.outer(offsets @ up, up)
    radius = float(np.median(np.linalg.norm(flat, axis=1)))
    e1 = flat[0] / np.linalg.norm(flat[0])
    e2 = np.cross(up, e1)
    first = records[0]
    out = []
    for k in range(frames):
        angle = 2 * np.pi * k / frames
        position = centre + height * up + radius * (np.cos(angle) * e1 + np.sin(angle) * e2)
        z = (centre - position) / np.linalg.norm(centre - position)
        x = np.cross(z, up)
        x /= np.linalg.norm(x)
        rotation = np.stack([x, np.cross(z, x), z])
        out.append({**{k2: first[k2] for k2 in ("width", "height", "fx", "fy", "cx", "cy")},
                    "name": f"{k:04d}.png", "R": rotation.tolist(), "t": (-rotation @ position).tolist()})
    return out


def blender_path(camera_name: str) -> list[dict]:
    """A Blender camera's path over the scene's frame range, as cameras.json records in the engine's world
    (an imported camera's upright frame undone)."""
    import bpy

    from addon.import_scene import engine_matrix

    scene = bpy.context.scene
    camera = bpy.data.objects.get(camera_name)
    if camera is None or camera.type != "CAMERA":
        raise EngineError(f"no camera object {camera_name!r} in the open .blend; name one of its cameras")
    width = round(scene.render.resolution_x * scene.render.resolution_percentage / 100)
    height = round(scene.render.resolution_y * scene.render.resolution_percentage / 100)
    records = []
    for k, frame in enumerate(range(scene.frame_start, scene.frame_end + 1)):
        scene.frame_set(frame)
        d = camera.data
        aspect = (scene.render.pixel_aspect_x, scene.render.pixel_aspect_y)
        records.append(camera_formats.colmap_record(f"{k:04d}.png", engine_matrix(camera), d.lens,
                                                    d.sensor_width, d.sensor_height, d.sensor_fit, d.shift_x,
                                                    d.shift_y, width, height, aspect))
    return records


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", required=True, help="the original training run")
    parser.add_argument("--removed", required=True, help="the removal's output folder (its removal.json)")
    parser.add_argument("--after", default="", help=".ply shown as 'after' (default: the removed scene)")
    parser.add_argument("--out", required=True, help="new folder for cameras.json, frames/ and turntable.mp4")
    parser.add_argument("--frames", type=int, default=48)
    parser.add_argument("--camera", default="", help="a Blender camera of the open .blend, over its frame range")
    parser.add_argument("--fps", type=int, default=24)
    parser.add_argument("--keep-frames", action="store_true", help="keep frames/, before/ and after/ beside the MP4")
    parser.add_argument("--device", default="auto")
    args = parser.parse_args(script_args(argv))
    run, removed, out = RunLayout(args.run), RemovedLayout(args.removed), Path(args.out)
    try:
        if out.exists():
            raise EngineError(f"{out} exists: name a new folder for the turntable")
        out.mkdir(parents=True)
        if args.camera:
            records = blender_path(args.camera)
        else:
            scene = json.loads(run.config_json.read_text())["scene"]
            run_engine(["cameras", "--scene", scene, "--out", str(out / "scene_cameras.json")])
            records = orbit(json.loads((out / "scene_cameras.json").read_text()), object_centre(run, removed),
                            args.frames)
        (out / "cameras.json").write_text(json.dumps(records, indent=1))
        after = Path(args.after) if args.after else removed.point_cloud
        for name, ply in (("before", run.point_cloud), ("after", after)):
            print(f"rendering {name}: {ply}", flush=True)
            run_engine(["render", "--ply", str(ply), "--cameras", str(out / "cameras.json"), "--out", str(out / name),
                        "--device", args.device])
        run_engine(["compare", "--per-view", "--out", str(out / "frames"), "--views",
                    *[r["name"] for r in records], "--columns", f"before={out / 'before'}", f"after={out / 'after'}"])
        video = out / "turntable.mp4"
        run_engine(["video", "--frames", str(out / "frames"), "--out", str(video), "--fps", str(args.fps)])
        if not args.keep_frames:
            for folder in ("frames", "before", "after"):
                shutil.rmtree(out / folder)
    except (EngineError, OSError, KeyError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(f"video: {video}" + (f"  frames: {out / 'frames'}" if args.keep_frames else ""), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
