"""Cameras on an orbit, Cycles settings, and the render loop writing multi-part EXRs.

Camera records use COLMAP's conventions (world-to-camera R, t; OpenCV axes; principal point at the
image centre in COLMAP's pixel convention), so the engine needs no Blender knowledge.
"""

from __future__ import annotations

import math
import random
import time
from pathlib import Path

import bpy
from mathutils import Matrix, Vector

LENS_MM, SENSOR_MM = 35.0, 36.0
BLENDER_TO_OPENCV = Matrix(((1, 0, 0), (0, -1, 0), (0, 0, -1)))


def configure_cycles(width: int, samples: int, seed: int, threads: int = 0) -> tuple[int, int]:
    """Cycles on the CPU, deterministic, with the passes we need; returns (width, height)."""
    scene = bpy.context.scene
    height = int(round(width * 3 / 4 / 2)) * 2
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_adaptive_sampling = False  # same sample pattern in images/ and gt/
    scene.cycles.use_denoising = True  # Monte Carlo noise is not view-consistent; 3DGS cannot fit it
    scene.cycles.seed = seed
    scene.cycles.max_bounces = 4
    scene.cycles.caustics_reflective = scene.cycles.caustics_refractive = False
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.threads_mode = "FIXED" if threads > 0 else "AUTO"
    scene.render.threads = max(threads, 1)
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"  # the engine applies the sRGB curve itself
    scene.view_settings.look = "None"
    scene.view_settings.exposure, scene.view_settings.gamma = 0.0, 1.0
    layer = scene.view_layers[0]
    layer.use_pass_z = True
    layer.use_pass_object_index = True
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):  # Blender 5.0 moved multilayer EXR behind media_type
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    return width, height


def orbit_poses(focus: Vector, distance: float, elevation: tuple[float, float], views: int, orbit: str,
                rng: random.Random, arc: float = 360.0, facing: float = 0.0) -> list[Matrix]:
    """Camera-to-world matrices (Blender axes) looking at `focus`.

    '360': one loop around the focus whose elevation weaves between the bounds three times, so that
    neighbouring views differ in height as in a hand-held capture; with `arc` under 360 degrees, one sweep over
    that arc around `facing` (a wall behind the focus). 'hemisphere': a Fibonacci spiral
    over elevations from the lower bound to 75 degrees.
    """
    lo, hi = elevation
    start = rng.uniform(0, 2 * math.pi)
    golden = math.pi * (3 - math.sqrt(5))
    poses = []
    for i in range(views):
        if orbit == "360" and arc < 360:  # a sweep in front of a wall, end to end
            azimuth = facing + math.radians(arc) * ((i + 0.5) / views - 0.5)
            elev = lo + (hi - lo) * (0.5 + 0.5 * math.sin(6 * math.pi * i / views))
        elif orbit == "360":
            azimuth = start + 2 * math.pi * i / views
            elev = lo + (hi - lo) * (0.5 + 0.5 * math.sin(6 * math.pi * i / views))
        else:
            s_lo, s_hi = math.sin(math.radians(lo)), math.sin(math.radians(75.0))
            elev = math.degrees(math.asin(s_lo + (s_hi - s_lo) * (i + 0.5) / views))
            azimuth = start + golden * i
        r = distance * rng.uniform(0.95, 1.05)
        e = math.radians(elev)
        location = focus + Vector((r * math.cos(e) * math.cos(azimuth), r * math.cos(e) * math.sin(azimuth),
                                   r * math.sin(e)))
        look = focus + Vector([rng.uniform(-0.02, 0.02) for _ in range(3)])
        rotation = (look - location).to_track_quat("-Z", "Y").to_matrix()
        poses.append(Matrix.Translation(location) @ rotation.to_4x4())
    return poses


def add_camera() -> bpy.types.Object:
    data = bpy.data.cameras.new("camera")
    data.lens, data.sensor_width, data.sensor_fit = LENS_MM, SENSOR_MM, "HORIZONTAL"
    data.clip_start, data.clip_end = 0.01, 100.0
    camera = bpy.data.objects.new("camera", data)
    bpy.context.scene.collection.objects.link(camera)
    bpy.context.scene.camera = camera
    return camera


def colmap_record(name: str, pose: Matrix, width: int, height: int) -> dict:
    """A camera in COLMAP's conventions: world-to-camera R, t with OpenCV axes; PINHOLE intrinsics."""
    f = LENS_MM / SENSOR_MM * width
    r_c2w = pose.to_3x3() @ BLENDER_TO_OPENCV
    r_w2c = r_c2w.transposed()
    t_w2c = -(r_w2c @ pose.translation)
    return {"name": name, "width": width, "height": height, "fx": f, "fy": f, "cx": width / 2, "cy": height / 2,
            "R": [list(row) for row in r_w2c], "t": list(t_w2c)}


def render_views(camera: bpy.types.Object, poses: list[Matrix], names: list[str], folder: Path,
                 label: str) -> None:
    """Render each pose to folder/<stem>.exr, printing one progress line per view."""
    folder.mkdir(parents=True, exist_ok=True)
    scene = bpy.context.scene
    start = time.monotonic()
    for k, (pose, name) in enumerate(zip(poses, names, strict=True)):
        camera.matrix_world = pose
        scene.render.filepath = str(folder / f"{Path(name).stem}.exr")
        bpy.ops.render.render(write_still=True)
        print(f"[make_scene] {label} {k + 1}/{len(poses)} ({time.monotonic() - start:.1f} s)", flush=True)
