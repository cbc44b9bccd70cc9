"""How imported splats look in Blender's viewport (EEVEE) and renders (Cycles): each Gaussian is an instanced
ico-sphere reaching as far as the rasterizer draws it, and its material draws the Gaussian, not the sphere.

A Gaussian of opacity o is drawn out to the Mahalanobis distance sqrt(2 ln(255 o)), where its alpha falls
under 1/255 (the rasterizer's cut), at most MAX_REACH (`reach`); one fainter than 1/255 not at all. The
instance is an icosahedron whose faces lie at that distance (its `extent`, in standard deviations, is the
reach over the icosahedron's inradius). The rasterizer stops at 3.33, but it blends 2D projections blurred
by 0.3 px and a ray here meets the Gaussian's exact closest approach; on a tiny livingroom run, Cycles against
the engine over 8 views: cap 3.33 25.38 dB (24.91 on the test view), 2.38 25.55 dB (26.50), in 0.74x the
time (docs/BENCHMARKS.md).
The shader works where the sphere is hit, in the instance's own coordinates (Texture Coordinate > Object),
in which the Gaussian is isotropic with standard deviation 1 / extent: the ray's closest approach to the
centre there is the Mahalanobis distance m a rasterizer evaluates, so alpha = opacity * exp(-m^2 / 2) on the
front face (the back face is clear). Colour is the SH colour towards the viewer, all bands the file has, with
the direction turned back into the splat's own frame (the instance's rotation and scale undone, so a frame
that stands the scene upright or an object the user moves carries its view-dependent colour along). The
engine's colours are picture values (sRGB-encoded, blended as such); the emission is their linear value, so
Blender's Standard view transform shows them as the engine renders them. A Density input draws a random share
of the Gaussians, for large scenes in the viewport.
"""

from __future__ import annotations

import bpy
import numpy as np

from .formats import splat_ply

NODE_GROUP = "splatfill splats"
MATERIAL = "splatfill gaussian"
MAX_REACH = 2.38  # standard deviations drawn at most (see the docstring)
MIN_ALPHA = 1.0 / 255.0  # the rasterizer skips fainter
INRADIUS = 0.7946  # Blender's ico sphere at 1 subdivision: its faces' distance from the centre, radius 1
NEAR_PLANE = 0.01  # the rasterizer's (engine.render.rasterize.NEAR_PLANE): nearer centres are not drawn
SH_ATTRIBUTES = tuple(f"sh_{k + 1}" for k in range(len(splat_ply.SH_POLYNOMIALS)))


def extents(opacity: np.ndarray) -> np.ndarray:
    """(N,) float32: each instance's radius in standard deviations (0: never drawn, too faint)."""
    reach = np.sqrt(2.0 * np.log(np.maximum(255.0 * opacity, 1.0)))
    return (np.minimum(reach, MAX_REACH) / INRADIUS).astype(np.float32)


def splat_node_group() -> bpy.types.NodeTree:
    """Instance on Points: an ico-sphere per kept vertex, rotated and scaled by its attributes, unrealized,
    with the group's Material; Density (0-1) keeps that random share of the vertices, of those drawn at all."""
    tree = bpy.data.node_groups.get(NODE_GROUP)
    if tree is not None:
        return tree
    tree = bpy.data.node_groups.new(NODE_GROUP, "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    density = tree.interface.new_socket("Density", in_out="INPUT", socket_type="NodeSocketFloat")
    density.default_value, density.min_value, density.max_value = 1.0, 0.0, 1.0
    tree.interface.new_socket("Material", in_out="INPUT", socket_type="NodeSocketMaterial")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = tree.nodes, tree.links
    group_in, group_out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    keep = nodes.new("FunctionNodeRandomValue")
    keep.data_type = "BOOLEAN"
    instance = nodes.new("GeometryNodeInstanceOnPoints")
    sphere = nodes.new("GeometryNodeMeshIcoSphere")
    sphere.inputs["Subdivisions"].default_value = 1
    rotation, scale = nodes.new("GeometryNodeInputNamedAttribute"), nodes.new("GeometryNodeInputNamedAttribute")
    rotation.data_type, scale.data_type = "QUATERNION", "FLOAT_VECTOR"
    rotation.inputs["Name"].default_value, scale.inputs["Name"].default_value = "rotation", "scale"
    material = nodes.new("GeometryNodeSetMaterial")
    links.new(group_in.outputs["Density"], keep.inputs["Probability"])
    links.new(group_in.outputs["Material"], material.inputs["Material"])
    links.new(group_in.outputs["Geometry"], instance.inputs["Points"])
    extent = nodes.new("GeometryNodeInputNamedAttribute")
    extent.data_type, extent.inputs["Name"].default_value = "FLOAT", "extent"
    drawn = nodes.new("FunctionNodeCompare")
    drawn.data_type, drawn.operation = "FLOAT", "GREATER_THAN"
    both = nodes.new("FunctionNodeBooleanMath")
    both.operation = "AND"
    links.new(extent.outputs["Attribute"], drawn.inputs["A"])
    links.new(keep.outputs[3], both.inputs[0])  # the boolean output
    links.new(drawn.outputs["Result"], both.inputs[1])
    links.new(both.outputs["Boolean"], instance.inputs["Selection"])
    links.new(sphere.outputs["Mesh"], material.inputs["Geometry"])
    links.new(material.outputs["Geometry"], instance.inputs["Instance"])
    links.new(rotation.outputs["Attribute"], instance.inputs["Rotation"])
    links.new(scale.outputs["Attribute"], instance.inputs["Scale"])
    links.new(instance.outputs["Instances"], group_out.inputs["Geometry"])
    return tree


def set_inputs(modifier: bpy.types.NodesModifier, **values) -> None:
    """Set the node group's inputs on one object's modifier by their names (Density, Material)."""
    for item in modifier.node_group.interface.items_tree:
        if getattr(item, "in_out", "") == "INPUT" and item.name in values:
            modifier[item.identifier] = values[item.name]


class _Nodes:
    """Shorthand for building a shader node tree: each call adds one node and links its inputs."""

    def __init__(self, tree: bpy.types.NodeTree):
        self.nodes, self.links = tree.nodes, tree.links

    def node(self, kind: str, inputs: dict | None = None, **settings) -> bpy.types.Node:
        node = self.nodes.new(kind)
        for key, value in settings.items():
            setattr(node, key, value)
        for index, value in (inputs or {}).items():
            if isinstance(value, bpy.types.NodeSocket):
                self.links.new(value, node.inputs[index])
            else:
                node.inputs[index].default_value = value
        return node

    def math(self, operation: str, *values) -> bpy.types.NodeSocket:
        return self.node("ShaderNodeMath", dict(enumerate(values)), operation=operation).outputs[0]

    def vector(self, operation: str, *values, scale: object = None) -> bpy.types.NodeSocket:
        node = self.node("ShaderNodeVectorMath", dict(enumerate(values)), operation=operation)
        if scale is not None:
            self.node_input(node, "Scale", scale)
        return node.outputs["Value" if operation in ("DOT_PRODUCT", "LENGTH", "DISTANCE") else "Vector"]

    def node_input(self, node: bpy.types.Node, name: str, value) -> None:
        socket = next(s for s in node.inputs if s.name == name and s.enabled)
        if isinstance(value, bpy.types.NodeSocket):
            self.links.new(value, socket)
        else:
            socket.default_value = value

    def attribute(self, name: str) -> bpy.types.Node:
        return self.node("ShaderNodeAttribute", attribute_type="INSTANCER", attribute_name=name)


def gaussian_material() -> bpy.types.Material:
    """The material every splat instance shares (see the module's docstring)."""
    material = bpy.data.materials.get(MATERIAL)
    if material is not None:
        return material
    material = bpy.data.materials.new(MATERIAL)
    material.use_nodes = True
    material.node_tree.nodes.clear()
    material.use_backface_culling = True  # EEVEE: only front faces draw (the shader clears back faces too)
    material.diffuse_color = (0.8, 0.8, 0.8, 1.0)
    n = _Nodes(material.node_tree)
    geometry = n.node("ShaderNodeNewGeometry")
    inside = n.node("ShaderNodeTexCoord").outputs["Object"]
    toward = n.node("ShaderNodeVectorTransform", {0: geometry.outputs["Incoming"]}, vector_type="VECTOR",
                    convert_from="WORLD", convert_to="OBJECT").outputs[0]
    alpha = _gaussian_alpha(n, inside, toward, geometry)
    colour = _sh_colour(n, _view_direction(n, toward))
    emission = n.node("ShaderNodeEmission", {"Color": _srgb_to_linear(n, colour), "Strength": 1.0})
    clear = n.node("ShaderNodeBsdfTransparent")
    mix = n.node("ShaderNodeMixShader", {0: alpha, 1: clear.outputs[0], 2: emission.outputs[0]})
    n.node("ShaderNodeOutputMaterial", {"Surface": mix.outputs[0]})
    return material


def _gaussian_alpha(n: _Nodes, inside, toward, geometry: bpy.types.Node) -> bpy.types.NodeSocket:
    """opacity * exp(-m^2 / 2), m the ray's closest approach to the centre in standard deviations; 0 on back
    faces and for a Gaussian whose centre lies behind the camera's near plane (the rasterizer culls those: a
    large one around the camera would otherwise veil the view); capped at 0.999 and 0 under 1/255, as the
    rasterizer has it."""
    direction = n.vector("NORMALIZE", toward)
    along = n.vector("DOT_PRODUCT", inside, direction)
    squared = n.math("SUBTRACT", n.vector("DOT_PRODUCT", inside, inside), n.math("MULTIPLY", along, along))
    extent = n.attribute("extent").outputs["Fac"]
    falloff = n.math("EXPONENT", n.math("MULTIPLY", n.math("MULTIPLY", squared, n.math("MULTIPLY", extent, extent)),
                                        -0.5))
    camera = lambda point: n.node("ShaderNodeSeparateXYZ", {0: n.node(  # noqa: E731
        "ShaderNodeVectorTransform", {0: point}, vector_type="POINT", convert_from="WORLD",
        convert_to="CAMERA").outputs[0]}).outputs[2]
    # camera-space z of the centre, signed by the hit point's (always in front: the engines' camera spaces
    # disagree on which way the camera looks)
    depth = n.math("MULTIPLY", camera(n.node("ShaderNodeObjectInfo").outputs["Location"]),
                   n.math("SIGN", camera(geometry.outputs["Position"])))
    ahead = n.math("GREATER_THAN", depth, NEAR_PLANE)
    front = n.math("MULTIPLY", n.math("SUBTRACT", 1.0, geometry.outputs["Backfacing"]), ahead)
    alpha = n.math("MULTIPLY", n.math("MULTIPLY", n.attribute("color").outputs["Alpha"], falloff), front)
    alpha = n.math("MINIMUM", alpha, 0.999)
    return n.math("MULTIPLY", alpha, n.math("GREATER_THAN", alpha, MIN_ALPHA))


def _view_direction(n: _Nodes, toward) -> bpy.types.NodeSocket:
    """The unit direction from the viewer to the Gaussian in the splat's own frame: `toward` (the direction to
    the viewer in the instance's coordinates) scaled back by the instance's scale and turned by its quaternion
    (v + 2w (u x v) + 2 u x (u x v), u its vector part)."""
    v = n.vector("MULTIPLY", toward, n.attribute("scale").outputs["Vector"])
    u, w = n.attribute("quat_xyz").outputs["Vector"], n.attribute("quat_w").outputs["Fac"]
    once = n.vector("CROSS_PRODUCT", u, v)
    twice = n.vector("CROSS_PRODUCT", u, once)
    turned = n.vector("MULTIPLY_ADD", n.vector("ADD", n.vector("SCALE", once, scale=w), twice), (2.0, 2.0, 2.0), v)
    return n.vector("SCALE", n.vector("NORMALIZE", turned), scale=-1.0)


def _sh_colour(n: _Nodes, direction) -> bpy.types.NodeSocket:
    """max(0, DC colour + sum over the higher bands of basis(direction) * coefficient); a band the .ply lacks
    reads as a zero attribute."""
    xyz = n.node("ShaderNodeSeparateXYZ", {0: direction}).outputs
    powers: dict[tuple[int, int, int], bpy.types.NodeSocket] = {}

    def monomial(exponents: tuple[int, int, int]):
        if exponents not in powers:
            factors = [xyz[axis] for axis, e in enumerate(exponents) for _ in range(e)]
            value = factors[0]
            for factor in factors[1:]:
                value = n.math("MULTIPLY", value, factor)
            powers[exponents] = value
        return powers[exponents]

    colour = n.attribute("color").outputs["Vector"]
    for name, terms in zip(SH_ATTRIBUTES, splat_ply.SH_POLYNOMIALS, strict=True):
        basis = None
        for coefficient, exponents in terms:
            term = n.math("MULTIPLY", monomial(exponents), coefficient)
            basis = term if basis is None else n.math("ADD", basis, term)
        colour = n.vector("MULTIPLY_ADD", n.attribute(name).outputs["Vector"], _splat(n, basis), colour)
    return n.vector("MAXIMUM", colour, (0.0, 0.0, 0.0))


def _splat(n: _Nodes, value) -> bpy.types.NodeSocket:
    """A float as a vector (x = y = z = value)."""
    return n.node("ShaderNodeCombineXYZ", {0: value, 1: value, 2: value}).outputs[0]


def _srgb_to_linear(n: _Nodes, colour) -> bpy.types.NodeSocket:
    """The sRGB transfer function undone per channel: c / 12.92 up to 0.04045, ((c + 0.055) / 1.055)^2.4 above."""
    low = n.vector("SCALE", colour, scale=1.0 / 12.92)
    high = n.vector("POWER", n.vector("MULTIPLY_ADD", colour, (1 / 1.055,) * 3, (0.055 / 1.055,) * 3), (2.4,) * 3)
    above = n.vector("MULTIPLY_ADD", n.vector("SIGN", n.vector("SUBTRACT", colour, (0.04045,) * 3)), (0.5,) * 3,
                     (0.5,) * 3)
    return n.vector("MULTIPLY_ADD", above, n.vector("SUBTRACT", high, low), low)
