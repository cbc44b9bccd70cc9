"""Building meshes from primitives with bmesh: parts with their own materials joined into one object.

Geometry is built at its real size (never by object scale) so that procedural textures driven by
object coordinates keep their scale in scene units.
"""

from __future__ import annotations

import bmesh
import bpy
from mathutils import Euler, Matrix, Vector, noise


class MeshBuilder:
    """Accumulates primitive parts into one mesh; each part names its material."""

    def __init__(self) -> None:
        self.bm = bmesh.new()
        self.materials: list[bpy.types.Material] = []

    def _place(self, geom: dict, material: bpy.types.Material, smooth: bool) -> list:
        if material not in self.materials:
            self.materials.append(material)
        index = self.materials.index(material)
        verts = geom["verts"]
        faces = {f for v in verts for f in v.link_faces}
        for face in faces:
            face.material_index = index
            face.smooth = smooth
        return verts

    @staticmethod
    def _matrix(location, rotation=(0, 0, 0)) -> Matrix:
        return Matrix.Translation(Vector(location)) @ Euler(rotation).to_matrix().to_4x4()

    def box(self, size, location, material, rotation=(0, 0, 0)) -> list:
        geom = bmesh.ops.create_cube(self.bm, size=1.0)
        bmesh.ops.scale(self.bm, vec=Vector(size), verts=geom["verts"])
        bmesh.ops.transform(self.bm, matrix=self._matrix(location, rotation), verts=geom["verts"])
        return self._place(geom, material, smooth=False)

    def sphere(self, radius, location, material, scale=(1, 1, 1), segments: int = 32,
               bumpiness: float = 0.0, seed: float = 0.0) -> list:
        geom = bmesh.ops.create_uvsphere(self.bm, u_segments=segments, v_segments=segments // 2, radius=radius)
        verts = geom["verts"]
        if bumpiness > 0:
            for v in verts:  # low-frequency noise displacement: rocks, blobs, plush
                n = noise.noise(v.co * (3.0 / radius) + Vector((seed, seed, seed)))
                v.co *= 1.0 + bumpiness * n
        bmesh.ops.scale(self.bm, vec=Vector(scale), verts=verts)
        bmesh.ops.translate(self.bm, vec=Vector(location), verts=verts)
        return self._place(geom, material, smooth=True)

    def cylinder(self, radius, depth, location, material, rotation=(0, 0, 0), radius_top=None,
                 segments: int = 32) -> list:
        geom = bmesh.ops.create_cone(self.bm, cap_ends=True, cap_tris=False, segments=segments,
                                     radius1=radius, radius2=radius if radius_top is None else radius_top,
                                     depth=depth)
        bmesh.ops.transform(self.bm, matrix=self._matrix(location, rotation), verts=geom["verts"])
        return self._place(geom, material, smooth=True)

    def plane(self, size_x, size_y, location, material) -> list:
        geom = bmesh.ops.create_grid(self.bm, x_segments=1, y_segments=1, size=0.5)
        bmesh.ops.scale(self.bm, vec=Vector((size_x, size_y, 1)), verts=geom["verts"])
        bmesh.ops.translate(self.bm, vec=Vector(location), verts=geom["verts"])
        return self._place(geom, material, smooth=False)

    def finish(self, name: str, pass_index: int = 0) -> bpy.types.Object:
        """Create the object (linked to the scene); `pass_index` is its id in the masks (0 = background)."""
        mesh = bpy.data.meshes.new(name)
        self.bm.normal_update()
        self.bm.to_mesh(mesh)
        self.bm.free()
        for material in self.materials:
            mesh.materials.append(material)
        obj = bpy.data.objects.new(name, mesh)
        obj.pass_index = pass_index
        bpy.context.scene.collection.objects.link(obj)
        return obj
