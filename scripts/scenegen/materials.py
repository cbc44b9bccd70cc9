"""Procedural materials with real detail (wood grain, stone, checker, noise), so inpainting quality shows.

Each material is a weighted sum of texture factors in object coordinates (scene units), mapped
through a colour ramp into a Principled BSDF, with the same sum driving a bump for lighting detail.
"""

from __future__ import annotations

import random

import bpy

Color = tuple[float, float, float]

TEXTURE_NODES = {
    "wave": ("ShaderNodeTexWave", "Fac"),
    "rings": ("ShaderNodeTexWave", "Fac"),
    "noise": ("ShaderNodeTexNoise", "Fac"),
    "voronoi": ("ShaderNodeTexVoronoi", "Distance"),
    "checker": ("ShaderNodeTexChecker", "Fac"),
    "brick": ("ShaderNodeTexBrick", "Fac"),
    "magic": ("ShaderNodeTexMagic", "Fac"),
}


def _new_material(name: str) -> bpy.types.Material:
    mat = bpy.data.materials.new(name)
    if not mat.use_nodes:  # Blender 4.x; in 5.x node trees are always on
        mat.use_nodes = True
    mat.node_tree.nodes.clear()
    return mat


def _texture_sum(tree: bpy.types.NodeTree, textures: list[dict]) -> bpy.types.NodeSocket:
    """Weighted sum of the factor outputs of `textures`, each {"kind", "scale", "weight", ...}."""
    coords = tree.nodes.new("ShaderNodeTexCoord").outputs["Object"]
    total = None
    for spec in textures:
        node_type, output = TEXTURE_NODES[spec["kind"]]
        node = tree.nodes.new(node_type)
        tree.links.new(coords, node.inputs["Vector"])
        node.inputs["Scale"].default_value = spec.get("scale", 5.0)
        if spec["kind"] in ("wave", "rings"):
            node.wave_type = "RINGS" if spec["kind"] == "rings" else "BANDS"
            node.inputs["Distortion"].default_value = spec.get("distortion", 4.0)
            node.inputs["Detail"].default_value = spec.get("detail", 3.0)
        if spec["kind"] == "noise":
            node.inputs["Detail"].default_value = spec.get("detail", 8.0)
        weighted = tree.nodes.new("ShaderNodeMath")
        weighted.operation = "MULTIPLY"
        tree.links.new(node.outputs[output], weighted.inputs[0])
        weighted.inputs[1].default_value = spec.get("weight", 1.0)
        if total is None:
            total = weighted.outputs[0]
        else:
            add = tree.nodes.new("ShaderNodeMath")
            add.operation = "ADD"
            tree.links.new(total, add.inputs[0])
            tree.links.new(weighted.outputs[0], add.inputs[1])
            total = add.outputs[0]
    return total


def _ramp(tree: bpy.types.NodeTree, fac: bpy.types.NodeSocket, colors: list[Color],
          span: tuple[float, float]) -> bpy.types.NodeSocket:
    ramp = tree.nodes.new("ShaderNodeValToRGB")
    tree.links.new(fac, ramp.inputs["Fac"])
    elements = ramp.color_ramp.elements
    while len(elements) < len(colors):
        elements.new(0.5)
    lo, hi = span
    for k, (element, color) in enumerate(zip(elements, colors, strict=True)):
        element.position = lo + (hi - lo) * k / (len(colors) - 1)
        element.color = (*color, 1.0)
    return ramp.outputs["Color"]


def textured(name: str, colors: list[Color], textures: list[dict], roughness: float = 0.6,
             span: tuple[float, float] = (0.3, 0.7), bump: float = 0.15) -> bpy.types.Material:
    """A diffuse-ish surface whose colour varies with procedural texture."""
    mat = _new_material(name)
    tree = mat.node_tree
    fac = _texture_sum(tree, textures)
    bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
    tree.links.new(_ramp(tree, fac, colors, span), bsdf.inputs["Base Color"])
    bsdf.inputs["Roughness"].default_value = roughness
    if bump > 0:
        bump_node = tree.nodes.new("ShaderNodeBump")
        bump_node.inputs["Strength"].default_value = bump
        tree.links.new(fac, bump_node.inputs["Height"])
        tree.links.new(bump_node.outputs["Normal"], bsdf.inputs["Normal"])
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def emissive(name: str, colors: list[Color], textures: list[dict], strength: float = 1.0) -> bpy.types.Material:
    """A self-lit backdrop (the surrounding dome): textured, independent of the lights."""
    mat = _new_material(name)
    tree = mat.node_tree
    emission = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(_ramp(tree, _texture_sum(tree, textures), colors, (0.3, 0.7)), emission.inputs["Color"])
    emission.inputs["Strength"].default_value = strength
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(emission.outputs[0], out.inputs["Surface"])
    return mat


def jitter(rng: random.Random, color: Color, amount: float = 0.08) -> Color:
    """A colour near `color`: the seed varies every palette a little."""
    return tuple(min(1.0, max(0.0, c + rng.uniform(-amount, amount))) for c in color)  # type: ignore[return-value]


def wood(rng: random.Random, name: str = "wood") -> bpy.types.Material:
    base = jitter(rng, (0.35, 0.18, 0.07))
    return textured(name, [tuple(c * 0.7 for c in base), base, jitter(rng, (0.5, 0.3, 0.14))],
                    [{"kind": "wave", "scale": rng.uniform(10, 16), "distortion": rng.uniform(6, 10),
                      "detail": 6.0},
                     {"kind": "noise", "scale": rng.uniform(40, 70), "weight": 0.3}],
                    roughness=0.45, span=(0.15, 1.0))


def checker(rng: random.Random, name: str, a: Color, b: Color) -> bpy.types.Material:
    return textured(name, [jitter(rng, a), jitter(rng, b)],
                    [{"kind": "checker", "scale": rng.uniform(6, 14)},
                     {"kind": "noise", "scale": rng.uniform(40, 80), "weight": 0.3}],
                    roughness=0.8, span=(0.2, 1.1), bump=0.05)


def weave(rng: random.Random, name: str, a: Color, b: Color) -> bpy.types.Material:
    """A woven place-mat look: fine bands crossed with a brick pattern."""
    return textured(name, [jitter(rng, a), jitter(rng, b)],
                    [{"kind": "brick", "scale": rng.uniform(8, 16)},
                     {"kind": "wave", "scale": rng.uniform(20, 40), "distortion": 1.0, "weight": 0.5}],
                    roughness=0.9, span=(0.4, 1.2), bump=0.2)


def stone(rng: random.Random, name: str = "stone", tint: Color = (0.45, 0.44, 0.42)) -> bpy.types.Material:
    t = jitter(rng, tint, 0.05)
    return textured(name, [tuple(c * 0.5 for c in t), t, tuple(min(1, c * 1.3) for c in t)],
                    [{"kind": "voronoi", "scale": rng.uniform(3, 7)},
                     {"kind": "noise", "scale": rng.uniform(10, 25), "weight": 0.6}],
                    roughness=0.85, span=(0.2, 0.9), bump=0.3)


def mottled(rng: random.Random, name: str, a: Color, b: Color, scale: float = 8.0) -> bpy.types.Material:
    return textured(name, [jitter(rng, a), jitter(rng, b)],
                    [{"kind": "noise", "scale": scale * rng.uniform(0.7, 1.4)},
                     {"kind": "magic", "scale": scale * 0.5, "weight": 0.2}],
                    roughness=0.5)
