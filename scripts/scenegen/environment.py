"""What every family shares: a self-lit dome so every pixel has a surface, a floor, sun and sky light."""

from __future__ import annotations

import math
import random

import bpy

from scenegen import materials
from scenegen.meshes import MeshBuilder

DOME_RADIUS = 9.0


def add_dome(rng: random.Random, colors: list[materials.Color]) -> bpy.types.Object:
    """A textured sphere seen only by camera rays: a backdrop with finite depth that lights nothing."""
    mat = materials.emissive("dome", [materials.jitter(rng, c, 0.05) for c in colors],
                             [{"kind": "noise", "scale": rng.uniform(0.6, 1.2), "detail": 6.0},
                              {"kind": "voronoi", "scale": rng.uniform(0.8, 1.5), "weight": 0.3}],
                             strength=1.0)
    builder = MeshBuilder()
    builder.sphere(DOME_RADIUS, (0, 0, 0), mat, segments=64)
    dome = builder.finish("dome")
    for ray in ("visible_diffuse", "visible_glossy", "visible_transmission", "visible_volume_scatter",
                "visible_shadow"):
        setattr(dome, ray, False)
    return dome


def add_floor(material: bpy.types.Material, size: float = 2 * DOME_RADIUS) -> bpy.types.Object:
    builder = MeshBuilder()
    builder.plane(size, size, (0, 0, 0), material)
    return builder.finish("floor")


def add_lights(rng: random.Random) -> None:
    """A sun (seeded direction and warmth) for crisp shadows, and a dim sky for fill."""
    sun = bpy.data.lights.new("sun", "SUN")
    sun.energy = rng.uniform(2.5, 4.0)
    sun.angle = math.radians(rng.uniform(2.0, 6.0))
    sun.color = materials.jitter(rng, (1.0, 0.95, 0.88), 0.05)
    obj = bpy.data.objects.new("sun", sun)
    obj.rotation_euler = (math.radians(rng.uniform(25, 50)), 0.0, rng.uniform(0, 2 * math.pi))
    bpy.context.scene.collection.objects.link(obj)
    world = bpy.data.worlds.new("sky")
    if not world.use_nodes:
        world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*materials.jitter(rng, (0.55, 0.6, 0.7), 0.05), 1.0)
    background.inputs["Strength"].default_value = rng.uniform(0.5, 0.8)
    bpy.context.scene.world = world
