"""Bring an engine scene into Blender: COLMAP cameras as Blender cameras, and a 3DGS .ply as point-instanced
proxies, one object per identity group, so that the Outliner lists the scene's objects.

The proxies are vertex-only meshes (bpy.data.pointclouds cannot be resized from Python) filled with
foreach_set from numpy, never a Python loop per Gaussian; a shared geometry-node group instances a small
ico-sphere on every vertex, rotated by the Gaussian's quaternion and scaled by its standard deviations,
and leaves the instances unrealized. A shared material colours each instance from its SH DC colour and
opacity (instance attributes). They are proxies for selecting and seeing the scene; the pictures that
count are rendered by the engine's rasterizer (scripts/turntable.py).
"""

from __future__ import annotations

from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix

from .formats import InputError, colmap_files
from .formats import cameras as camera_formats
from .splat_ply import Splats, read_splats, scene_of

NODE_GROUP = "splatfill proxy"
MATERIAL = "splatfill splat"
UPRIGHT_TOLERANCE_DEG = 1.0  # a scene tilted less than this is shown as it is
PROXY_SIGMAS = 2.0  # instance radius in standard deviations: a 2-sigma ellipsoid holds most of a Gaussian


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
    """One proxy object per identity group of the .ply at `path`, linked into `collection`, upright when the
    .ply belongs to a run whose scene is known."""
    splats = read_splats(Path(path))
    frame = upright_frame(scene_of(Path(path)), collection)
    group_tree, material = proxy_node_group(), splat_material()
    order = np.argsort(splats.groups, kind="stable")
    ids, starts = np.unique(splats.groups[order], return_index=True)
    objects = []
    for gid, index in zip(ids, np.split(order, starts[1:]), strict=True):
        name = splats.names.get(int(gid), f"object_{gid}")
        mesh = _proxy_mesh(name, splats, index)
        obj = bpy.data.objects.new(name, mesh)
        obj["splatfill_group"] = int(gid)
        obj["splatfill_ply"] = str(path)
        modifier = obj.modifiers.new("splatfill proxy", "NODES")
        modifier.node_group = group_tree
        obj.data.materials.append(material)
        _link(obj, collection, frame)
        objects.append(obj)
    collection["splatfill_ply"] = str(path)
    return objects


def _proxy_mesh(name: str, splats: Splats, index: np.ndarray) -> bpy.types.Mesh:
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(index))
    mesh.vertices.foreach_set("co", splats.positions[index].ravel())
    mesh.attributes.new("gaussian", "INT", "POINT").data.foreach_set("value", index.astype(np.int32))
    for attr, kind, values in (("rotation", "QUATERNION", splats.rotations[index]),
                               ("scale", "FLOAT_VECTOR", splats.scales[index] * PROXY_SIGMAS),
                               ("color", "FLOAT_COLOR", splats.colors[index])):
        layer = mesh.attributes.new(attr, kind, "POINT")
        field = {"QUATERNION": "value", "FLOAT_VECTOR": "vector", "FLOAT_COLOR": "color"}[kind]
        layer.data.foreach_set(field, values.ravel())
    mesh.update()
    return mesh


def proxy_node_group() -> bpy.types.NodeTree:
    """Instance on Points: an ico-sphere per vertex, rotated and scaled by its attributes, unrealized."""
    tree = bpy.data.node_groups.get(NODE_GROUP)
    if tree is not None:
        return tree
    tree = bpy.data.node_groups.new(NODE_GROUP, "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = tree.nodes, tree.links
    group_in, group_out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    instance = nodes.new("GeometryNodeInstanceOnPoints")
    sphere = nodes.new("GeometryNodeMeshIcoSphere")
    sphere.inputs["Subdivisions"].default_value = 1
    rotation, scale = nodes.new("GeometryNodeInputNamedAttribute"), nodes.new("GeometryNodeInputNamedAttribute")
    rotation.data_type, scale.data_type = "QUATERNION", "FLOAT_VECTOR"
    rotation.inputs["Name"].default_value, scale.inputs["Name"].default_value = "rotation", "scale"
    material = nodes.new("GeometryNodeSetMaterial")
    material.inputs["Material"].default_value = splat_material()
    links.new(group_in.outputs[0], instance.inputs["Points"])
    links.new(sphere.outputs["Mesh"], material.inputs["Geometry"])
    links.new(material.outputs["Geometry"], instance.inputs["Instance"])
    links.new(rotation.outputs["Attribute"], instance.inputs["Rotation"])
    links.new(scale.outputs["Attribute"], instance.inputs["Scale"])
    links.new(instance.outputs["Instances"], group_out.inputs[0])
    return tree


def splat_material() -> bpy.types.Material:
    """Emission in the instance's SH DC colour, mixed with transparency by its opacity."""
    material = bpy.data.materials.get(MATERIAL)
    if material is not None:
        return material
    material = bpy.data.materials.new(MATERIAL)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    attribute = nodes.new("ShaderNodeAttribute")
    attribute.attribute_type, attribute.attribute_name = "INSTANCER", "color"
    emission, transparent = nodes.new("ShaderNodeEmission"), nodes.new("ShaderNodeBsdfTransparent")
    mix, output = nodes.new("ShaderNodeMixShader"), nodes.new("ShaderNodeOutputMaterial")
    links.new(attribute.outputs["Color"], emission.inputs["Color"])
    links.new(attribute.outputs["Alpha"], mix.inputs["Fac"])
    links.new(transparent.outputs[0], mix.inputs[1])
    links.new(emission.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], output.inputs["Surface"])
    material.diffuse_color = (0.8, 0.8, 0.8, 1.0)
    return material
