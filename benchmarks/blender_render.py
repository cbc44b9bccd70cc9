"""How close a render through Blender of an imported run comes to the engine's own render of the same camera.

    .venv-blender/bin/python benchmarks/blender_render.py --run RUN [--ply PLY] [--views 0005.png ...]
        [--engine cycles|eevee] [--out DIR] [--json OUT.json]

Imports the run's scene cameras and its .ply (addon.import_scene, as the Import buttons do), renders each view
(the scene's test views by default) through Blender, renders the same cameras with the engine (`engine render`,
in the engine's Python), and reports PSNR per view and overall. Cycles renders one sample per pixel through
its centre (pixel filter 0.01 px), as the rasterizer samples, with up to 1024 transparent bounces; the world
is black, as the engine's background. DIR gets both sets of PNGs and a side-by-side picture (engine |
Blender) per view; --json a record with the commit and every setting.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
import bpy  # noqa: E402

from addon.engine_call import run_engine  # noqa: E402
from addon.formats import checks, layout  # noqa: E402
from addon.import_scene import import_cameras, import_splats  # noqa: E402


def set_up_render(engine: str) -> None:
    """Render settings under which Blender samples the splats as the rasterizer does (see the docstring)."""
    scene = bpy.context.scene
    scene.render.engine = "CYCLES" if engine == "cycles" else "BLENDER_EEVEE"
    if engine == "cycles":
        scene.cycles.device = "CPU"
        scene.cycles.samples, scene.cycles.use_adaptive_sampling, scene.cycles.use_denoising = 1, False, False
        scene.cycles.filter_width = 0.01
        scene.cycles.transparent_max_bounces = scene.cycles.min_transparent_bounces = 1024  # no roulette
    else:
        scene.eevee.taa_render_samples = 64
    world = bpy.data.worlds.new("black")
    world.color = (0.0, 0.0, 0.0)
    for node in world.node_tree.nodes if world.node_tree else ():
        if node.bl_idname == "ShaderNodeBackground":
            node.inputs["Strength"].default_value = 0.0
    scene.world = world
    scene.render.film_transparent = False
    scene.view_settings.view_transform, scene.view_settings.look = "Standard", "None"
    scene.view_settings.exposure, scene.view_settings.gamma = 0.0, 1.0
    scene.render.image_settings.file_format, scene.render.image_settings.color_mode = "PNG", "RGB"
    scene.render.image_settings.color_depth = "8"


def read_rgb(path: Path) -> np.ndarray:
    """(H, W, 3) float in [0, 1] of an 8-bit PNG, top row first (Blender's pixels start at the bottom)."""
    image = bpy.data.images.load(str(path))
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)[::-1, :, :3]


def psnr(a: np.ndarray, b: np.ndarray) -> float:
    mse = float(np.mean((a - b) ** 2))
    return 10 * math.log10(1.0 / mse) if mse > 0 else float("inf")


def compare(run: Path, ply: Path, views: list[str], out: Path, engine: str = "cycles") -> dict:
    """compare_cameras on the run's scene cameras (its test views unless `views` names others)."""
    scene_dir = Path(checks.read_json(layout.RunLayout(run).config_json)["scene"])
    views = views or checks.read_json(layout.SceneLayout(scene_dir).split_json)["test"]
    cameras = out / "cameras.json"
    run_engine(["cameras", "--scene", str(scene_dir), "--out", str(cameras)])
    chosen = [c for c in json.loads(cameras.read_text()) if c["name"] in views]
    (out / "views.json").write_text(json.dumps(chosen))
    return compare_cameras(ply, out / "views.json", out, engine, scene_dir)


def compare_cameras(ply: Path, cameras_json: Path, out: Path, engine: str = "cycles",
                    scene_dir: Path | None = None) -> dict:
    """Per-view PSNR (dB) of Blender's render of `ply` against the engine's, for each camera of a cameras.json
    (engine.formats.cameras), and seconds per Blender view."""
    chosen = json.loads(Path(cameras_json).read_text())
    run_engine(["render", "--ply", str(ply), "--cameras", str(cameras_json), "--out", str(out / "engine"),
                "--device", "cpu"])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    collection = bpy.data.collections.new("compare")
    bpy.context.scene.collection.children.link(collection)
    import_cameras(Path(cameras_json), collection, scene_dir)
    import_splats(ply, collection)
    set_up_render(engine)
    scene, scores, seconds = bpy.context.scene, {}, []
    (out / "blender").mkdir()
    for camera in chosen:
        obj = next(o for o in collection.objects if o.get("splatfill_image") == camera["name"])
        scene.camera = obj
        scene.render.resolution_x, scene.render.resolution_y = obj["splatfill_resolution"]
        scene.render.pixel_aspect_x, scene.render.pixel_aspect_y = obj["splatfill_pixel_aspect"]
        scene.render.filepath = str(out / "blender" / camera["name"])
        start = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        seconds.append(time.perf_counter() - start)
        scores[camera["name"]] = round(psnr(read_rgb(out / "blender" / camera["name"]),
                                            read_rgb(out / "engine" / camera["name"])), 2)
    run_engine(["compare", "--columns", f"engine={out / 'engine'}", f"blender {engine}={out / 'blender'}",
                "--views", *scores, "--out", str(out / "side_by_side.png")])
    return {"psnr": scores, "mean_psnr": round(float(np.mean(list(scores.values()))), 2),
            "seconds_per_view": round(float(np.mean(seconds)), 2), "gaussians": _gaussians(collection)}


def _gaussians(collection: bpy.types.Collection) -> int:
    return sum(len(o.data.vertices) for o in collection.objects if o.type == "MESH")


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--run", required=True, help="a trained run folder (its config.json names the scene)")
    parser.add_argument("--ply", help="the .ply to import (default RUN/point_cloud.ply)")
    parser.add_argument("--views", nargs="*", default=[], help="image names (default: the scene's test views)")
    parser.add_argument("--engine", choices=("cycles", "eevee"), default="cycles")
    parser.add_argument("--out", help="new folder for the renders (default: a temporary one)")
    parser.add_argument("--json", help="also write the numbers here as a record")
    args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    run = Path(args.run)
    ply = Path(args.ply) if args.ply else layout.RunLayout(run).point_cloud
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="splatfill-blender-render-"))
    out.mkdir(parents=True, exist_ok=bool(not args.out))
    result = compare(run, ply, args.views, out, args.engine)
    print(json.dumps(result, indent=1))
    if args.json:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=REPO)
        record = {"commit": commit.stdout.strip(), "blender": bpy.app.version_string, "command": sys.argv,
                  "settings": {"engine": args.engine, "run": str(run), "ply": str(ply), "views": args.views},
                  **result}
        Path(args.json).write_text(json.dumps(record, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
