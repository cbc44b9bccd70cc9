"""Commands that read a scene folder: build one from the generator's renders, summarise it, picture it, and
write its cameras for Blender-side code."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from engine.base.progress import emit, say


@dataclass
class BuildSceneConfig:
    renders: str = ""  # make_scene.py's renders folder (with/ without/ cameras.json ...)
    out: str = ""  # the new scene folder
    max_points: int = 30_000  # sparse points written to the COLMAP model
    seed: int = 0  # random seed of the points' sampling


def build_scene(config: BuildSceneConfig) -> None:
    from engine.capture.scene_build import BuildConfig, build_scene

    build_scene(Path(config.renders), Path(config.out), BuildConfig(max_points=config.max_points, seed=config.seed))


@dataclass
class SceneConfig:
    scene: str = ""  # the scene folder
    resolution: int = 1  # load at 1/N of the size (1, 2, 4, 8)


def info(config: SceneConfig) -> None:
    from engine.capture.scene import load_scene
    from engine.io.extent import describe_extent

    scene = load_scene(config.scene, config.resolution, depth=True)
    cam = scene.cameras[0]
    say(f"{scene.root}: {len(scene.cameras)} views ({len(scene.train)} train, {len(scene.test)} test), "
        f"{cam.width}x{cam.height}, {len(scene.points)} points")
    for obj in scene.objects:
        say(f"  object {obj.id}: {obj.name}{' (target)' if obj.target else ''}")
    say(f"  masks: {scene.masks is not None}, depth: {scene.depths is not None}, gt views: {len(scene.gt_images)}, "
        f"hole masks: {len(scene.holes)}")
    say(f"  sparse points lie in {describe_extent(scene.points)} (1st to 99th percentile; --box takes this frame)")


@dataclass
class PreviewConfig:
    scene: str = ""  # the scene folder
    out: str = ""  # PNG file to write
    rows: int = 3  # number of views shown
    resolution: int = 1  # load at 1/N of the size (1, 2, 4, 8)


def preview(config: PreviewConfig) -> None:
    from engine.capture.scene import load_scene
    from engine.pictures.preview import write_scene_preview

    scene = load_scene(config.scene, config.resolution, depth=True)
    say(f"wrote {write_scene_preview(scene, Path(config.out), rows=config.rows)}")


@dataclass
class CamerasConfig:
    scene: str = ""  # the scene folder (its COLMAP model)
    out: str = ""  # JSON file to write


def cameras(config: CamerasConfig) -> None:
    from engine.formats.cameras import write_cameras_json
    from engine.formats.colmap_files import find_model_dir
    from engine.io.colmap_model import read_model

    path = write_cameras_json(read_model(find_model_dir(Path(config.scene))).cameras, Path(config.out))
    emit("done", stage="cameras", out=str(path))
