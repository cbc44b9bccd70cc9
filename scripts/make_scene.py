"""Make a procedural 360-degree scene with exact ground truth for object removal.

    blender -b -P scripts/make_scene.py -- --family livingroom --out scenes/living [options]
    .venv-blender/bin/python scripts/make_scene.py --family livingroom --out scenes/living [options]

Blender renders (Cycles) the views with and without the target object as multi-part EXRs; the engine
(`python -m engine build-scene`, in its own environment) turns them into the scene folder described
in engine/capture/scene.py. The same arguments give the same scene.
"""

from __future__ import annotations

import argparse
import json
import random
import shutil
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from blender_entry import REPO_ROOT, add_repo_to_path, script_args  # noqa: E402

add_repo_to_path()

import bpy  # noqa: E402
from mathutils import noise  # noqa: E402
from scenegen import environment, render  # noqa: E402
from scenegen.families import FAMILIES  # noqa: E402

from addon.engine_call import EngineError, run_engine  # noqa: E402
from engine.formats.layout import RendersLayout  # noqa: E402

TEST_EVERY = 10  # about 90/10 train/test, as in the paper
EXTRA_TEST = 60  # test-only views beyond those: FID/KID need 50 images a side (engine.metrics.scores)
# Sizes by name; a flag given on the command line wins over its preset's value. `benchmark`: the held-out table's
# scenes (docs/BENCHMARKS.md, "Held-out table"): small enough that eight of them render on a 2-core machine well
# within an hour, with ground truth on every view (hole masks and removal are scored on the training views too)
# and 50 extra test views for the set metrics.
PRESETS = {"default": {}, "benchmark": dict(views=48, res=320, samples=8, gt="all", extra_test=50)}


@dataclass
class SceneConfig:
    family: str = "tabletop"
    out: str = "scene"
    views: int = 100
    res: int = 640
    samples: int = 64
    seed: int = 0
    orbit: str = "360"
    gt: str = "all"
    threads: int = 0
    points: int = 30_000
    extra_test: int = EXTRA_TEST
    preset: str = "default"


def parse_args(argv: list[str]) -> SceneConfig:
    parser = argparse.ArgumentParser(prog="make_scene.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--family", choices=sorted(FAMILIES), required=True)
    parser.add_argument("--preset", choices=sorted(PRESETS), default="default",
                        help="sizes by name (benchmark: the held-out table's); the flags below override it")
    parser.add_argument("--out", required=True, help="new folder for the scene")
    parser.add_argument("--views", type=int, default=SceneConfig.views)
    parser.add_argument("--res", type=int, default=SceneConfig.res, help="image width in pixels (height = 3/4)")
    parser.add_argument("--samples", type=int, default=SceneConfig.samples, help="Cycles samples per pixel")
    parser.add_argument("--seed", type=int, default=SceneConfig.seed)
    parser.add_argument("--orbit", choices=["360", "hemisphere"], default=SceneConfig.orbit)
    parser.add_argument("--gt", choices=["all", "test"], default=SceneConfig.gt,
                        help="render gt/ for every view or only for test views")
    parser.add_argument("--threads", type=int, default=SceneConfig.threads, help="render threads (0 = all cores)")
    parser.add_argument("--points", type=int, default=SceneConfig.points, help="sparse points in the COLMAP model")
    parser.add_argument("--extra-test", type=int, default=SceneConfig.extra_test,
                        help="test-only views on an orbit of their own, beyond the 1 in 10 of --views: the set "
                             "metrics' images (0 for a quick scene)")
    preset = parser.parse_known_args(argv)[0].preset
    parser.set_defaults(**PRESETS.get(preset, {}))
    args = parser.parse_args(argv)
    if args.views < 2 or args.res < 16 or args.samples < 1 or args.extra_test < 0:
        parser.error("need --views >= 2, --res >= 16, --samples >= 1 and --extra-test >= 0")
    return SceneConfig(**vars(args))


def split_views(names: list[str], extra: list[str] = ()) -> dict[str, list[str]]:
    """1 in TEST_EVERY of the orbit's views is a test view (views 5, 15, 25, ...; at least one), and every `extra`
    view is one."""
    offset = min(TEST_EVERY // 2, len(names) - 1)
    test = [n for i, n in enumerate(names) if i % TEST_EVERY == offset]
    return {"train": [n for n in names if n not in test], "test": [*test, *extra]}


def build_blender_scene(config: SceneConfig):
    """Model the family's scene from the seed; returns its SceneSpec."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rng = random.Random(f"{config.family}:{config.seed}")
    noise.seed_set(config.seed)
    spec = FAMILIES[config.family](rng)
    environment.add_dome(rng, [(0.55, 0.6, 0.65), (0.75, 0.72, 0.62), (0.4, 0.45, 0.35)])
    environment.add_lights(rng)
    return spec, rng


def render_scene(config: SceneConfig, staging: Path) -> None:
    spec, rng = build_blender_scene(config)
    width, height = render.configure_cycles(config.res, config.samples, config.seed, config.threads)
    camera = render.add_camera()
    poses = render.orbit_poses(spec.focus, spec.distance, spec.elevation, config.views, config.orbit, rng,
                               spec.arc, spec.facing)
    # the extra test views: an orbit of their own (another start, so between the training views), drawn after the
    # training views' so that a scene's training views are the same with or without them
    poses += render.orbit_poses(spec.focus, spec.distance, spec.elevation, config.extra_test, config.orbit, rng,
                                spec.arc, spec.facing) if config.extra_test else []
    names = [f"{i:04d}.png" for i in range(config.views + config.extra_test)]
    split = split_views(names[:config.views], names[config.views:])
    objects = [{"id": obj.pass_index, "name": obj.name, "target": target} for obj, target in spec.objects]
    renders = RendersLayout(staging)
    renders.cameras_json.write_text(json.dumps(
        [render.colmap_record(n, p, width, height) for n, p in zip(names, poses, strict=True)], indent=1))
    renders.objects_json.write_text(json.dumps(objects, indent=1))
    renders.split_json.write_text(json.dumps(split, indent=1))
    renders.meta_json.write_text(json.dumps(
        {"generator": "scripts/make_scene.py", "blender": bpy.app.version_string, **asdict(config)}, indent=1))
    render.render_views(camera, poses, names, renders.with_object, "images")
    spec.target.hide_render = True
    gt_names = names if config.gt == "all" else split["test"]
    gt_poses = [poses[names.index(n)] for n in gt_names]
    render.render_views(camera, gt_poses, gt_names, renders.without_object, "gt")


def main(argv: list[str]) -> int:
    config = parse_args(argv)
    out = Path(config.out).resolve()
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        print(f"error: output {out} already exists and is not empty: choose a new folder or delete it",
              file=sys.stderr)
        return 2
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.renders-", dir=out.parent))
    start = time.monotonic()
    try:
        render_scene(config, staging)
        run_engine(["build-scene", "--renders", str(staging), "--out", str(out), "--max-points", str(config.points)])
    except EngineError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    print(f"[make_scene] wrote {out} in {time.monotonic() - start:.1f} s (repo {REPO_ROOT})", flush=True)
    return 0


if __name__ == "__main__":
    code = main(script_args())
    if bpy.app.background and bpy.app.binary_path:
        sys.exit(code)  # under `blender -b -P`, end Blender with the script's status
    elif code:
        sys.exit(code)
