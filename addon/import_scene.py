"""Bring an engine scene into Blender: COLMAP cameras as Blender cameras, and a 3DGS .ply as point-instanced
splats, one object per identity group, so that the Outliner lists the scene's objects.

Each object is a vertex-only mesh (bpy.data.pointclouds cannot be resized from Python), one vertex per
Gaussian, filled with foreach_set from numpy, never a Python loop per Gaussian; its vertices carry what the
shared geometry-node group and material of addon.splat_shading need to draw each one as a Gaussian
(rotation, scale, colour and opacity, SH bands). Selecting vertices selects Gaussians (the `gaussian`
attribute is the index in the .ply).
"""

from __future__ import annotations

from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix

from .formats import InputError, colmap_files
from .formats import cameras as camera_formats
from .splat_ply import Splats, read_splats, scene_of
from .splat_shading import SH_ATTRIBUTES, extents, gaussian_material, set_inputs, splat_node_group

UPRIGHT_TOLERANCE_DEG = 1.0  # a scene tilted less than this is shown as it is
SHOWN = 2_000_000  # Gaussians drawn at most on import (the Density input of each object; the rest are kept)


def upright_frame(scene_root: Path | None, collection: bpy.types.Collection) -> bpy.types.Object | None:
    """An empty that stands the scene upright (its cameras' mean up turned to +Z, engine.formats.cameras):
    what is imported becomes its child, so an object's own coordinates stay the engine's (selections and
    boxes read there) while the viewport shows the capture the right way up. None without a scene, or for
    one upright already."""
    if scene_root is None:
        return None
    try:
        rotation = camera_formats.upright_rotation(colmap_files.world_to_camera_rotations(scene_root))
    except InputError:
        return None
    if np.degrees(np.arccos(np.clip((np.trace(rotation) - 1) / 2, -1, 1))) < UPRIGHT_TOLERANCE_DEG:
        return None  # upright already (our generated scenes): nothing to add
    frame = bpy.data.objects.new(f"{collection.name} frame", None)
    frame.empty_display_type = "ARROWS"
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    frame.matrix_world = Matrix(matrix.tolist())
    frame["splatfill_frame"] = str(scene_root)
    collection.objects.link(frame)
    return frame


def engine_matrix(obj: bpy.types.Object, frame: bpy.types.Object | None = None) -> np.ndarray:
    """(4, 4) `obj`'s matrix in the engine's world, undoing the upright frame it is parented to, or else
    `frame` (an object the user placed in the upright view, such as a cube around what to select)."""
    matrix = obj.matrix_world
    if obj.parent is not None and "splatfill_frame" in obj.parent:
        frame = obj.parent
    if frame is not None:
        matrix = frame.matrix_world.inverted() @ matrix
    return np.array(matrix)


def _link(obj: bpy.types.Object, collection: bpy.types.Collection, frame: bpy.types.Object | None,
          matrix: Matrix | None = None) -> None:
    """Link `obj`, placed at `matrix` (engine world), under `frame` when there is one."""
    collection.objects.link(obj)
    matrix = matrix if matrix is not None else Matrix.Identity(4)
    if frame is not None:
        obj.parent = frame
        matrix = frame.matrix_world @ matrix  # the object's own (basis) matrix stays in the engine's world
    obj.matrix_world = matrix


def import_cameras(cameras_json: Path, collection: bpy.types.Collection, scene_root: Path | None = None
                   ) -> list[bpy.types.Object]:
    """One Blender camera per camera of a cameras.json (engine.formats.cameras); the scene takes the first one's
    resolution and pixel aspect (they are per scene in Blender), each camera keeps its own as properties.
    With the scene's folder, they stand in its upright frame."""
    objects = []
    scene = bpy.context.scene
    frame = upright_frame(scene_root, collection)
    for k, c in enumerate(camera_formats.read_cameras_json(cameras_json)):
        settings = camera_formats.blender_settings(c.fx, c.fy, c.cx, c.cy, c.width, c.height)
        data = bpy.data.cameras.new(Path(c.name).stem)
        for key in ("sensor_fit", "sensor_width", "sensor_height", "lens", "shift_x", "shift_y"):
            setattr(data, key, settings[key])
        obj = bpy.data.objects.new(Path(c.name).stem, data)
        obj["splatfill_image"] = c.name
        obj["splatfill_resolution"] = list(settings["resolution"])
        obj["splatfill_pixel_aspect"] = list(settings["pixel_aspect"])
        _link(obj, collection, frame, Matrix(camera_formats.camera_to_world(c.R, c.t).tolist()))
        if k == 0:
            scene.render.resolution_x, scene.render.resolution_y = settings["resolution"]
            scene.render.resolution_percentage = 100
            scene.render.pixel_aspect_x, scene.render.pixel_aspect_y = settings["pixel_aspect"]
            scene.camera = obj
        objects.append(obj)
    return objects


def import_splats(path: Path, collection: bpy.types.Collection) -> list[bpy.types.Object]:
    """One object per identity group of the .ply at `path`, linked into `collection`, upright when the .ply
    belongs to a run whose scene is known. A scene of more than SHOWN Gaussians draws that many at random
    (each object's Density); the scene's view transform becomes Standard, which shows the splats' colours
    as the engine renders them (AgX, Blender's default, would tone-map them)."""
    splats = read_splats(Path(path))
    frame = upright_frame(scene_of(Path(path)), collection)
    group_tree, material = splat_node_group(), gaussian_material()
    density = min(1.0, SHOWN / max(len(splats.positions), 1))
    bpy.context.scene.view_settings.view_transform = "Standard"
    order = np.argsort(splats.groups, kind="stable")
    ids, starts = np.unique(splats.groups[order], return_index=True)
    objects = []
    for gid, index in zip(ids, np.split(order, starts[1:]), strict=True):
        name = splats.names.get(int(gid), f"object_{gid}")
        mesh = _proxy_mesh(name, splats, index)
        obj = bpy.data.objects.new(name, mesh)
        obj["splatfill_group"] = int(gid)
        obj["splatfill_ply"] = str(path)
        modifier = obj.modifiers.new("splatfill splats", "NODES")
        modifier.node_group = group_tree
        set_inputs(modifier, Density=density, Material=material)
        _link(obj, collection, frame)
        objects.append(obj)
    collection["splatfill_ply"] = str(path)
    return objects


def _proxy_mesh(name: str, splats: Splats, index: np.ndarray) -> bpy.types.Mesh:
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(index))
    mesh.vertices.foreach_set("co", splats.positions[index].ravel())
    mesh.attributes.new("gaussian", "INT", "POINT").data.foreach_set("value", index.astype(np.int32))
    rotations, extent = splats.rotations[index], extents(splats.colors[index, 3])
    layers = [("rotation", "QUATERNION", rotations), ("quat_xyz", "FLOAT_VECTOR", rotations[:, 1:]),
              ("quat_w", "FLOAT", rotations[:, 0]), ("extent", "FLOAT", extent),
              ("scale", "FLOAT_VECTOR", splats.scales[index] * extent[:, None]),
              ("color", "FLOAT_COLOR", splats.colors[index])]
    layers += [(name, "FLOAT_VECTOR", splats.sh_rest[index, k]) for k, name in
               enumerate(SH_ATTRIBUTES[: splats.sh_rest.shape[1]])]
    for attr, kind, values in layers:
        layer = mesh.attributes.new(attr, kind, "POINT")
        field = {"QUATERNION": "value", "FLOAT_VECTOR": "vector", "FLOAT_COLOR": "color", "FLOAT": "value"}[kind]
        layer.data.foreach_set(field, np.ascontiguousarray(values, np.float32).ravel())
    mesh.update()
    return mesh
