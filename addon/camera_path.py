"""A Blender camera's path over the scene's frame range as cameras.json records in the engine's world (an
imported camera's upright frame undone): what the turntable follows instead of its orbit (scripts/turntable.py
--camera, and the add-on's Turntable operator with the scene camera)."""

from __future__ import annotations

import bpy

from .formats import InputError
from .formats import cameras as camera_formats
from .import_scene import engine_matrix


def camera_path(camera: bpy.types.Object, scene: bpy.types.Scene) -> list[dict]:
    if camera is None or camera.type != "CAMERA":
        raise InputError("no camera to follow: name a camera object of the open .blend (or set the scene camera)")
    width = round(scene.render.resolution_x * scene.render.resolution_percentage / 100)
    height = round(scene.render.resolution_y * scene.render.resolution_percentage / 100)
    aspect = (scene.render.pixel_aspect_x, scene.render.pixel_aspect_y)
    current, records = scene.frame_current, []
    for k, frame in enumerate(range(scene.frame_start, scene.frame_end + 1)):
        scene.frame_set(frame)
        d = camera.data
        records.append(camera_formats.colmap_record(f"{k:04d}.png", engine_matrix(camera), d.lens, d.sensor_width,
                                                    d.sensor_height, d.sensor_fit, d.shift_x, d.shift_y, width,
                                                    height, aspect))
    scene.frame_set(current)
    return records
