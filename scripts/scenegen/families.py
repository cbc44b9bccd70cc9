"""The three scene families, modelled on the paper's scenes; the seed varies layout, shapes, textures, light.

- tabletop (the kitchen scene): a toy on two overlapping mats on a wooden table.
- statue (the bear scene): a statue on a plinth on a stone slab, clutter around, a small white object
  on the slab that must stay.
- livingroom (the occlusion case): a large plush-like object on a table hiding smaller objects.
- wallmount (a vertical support): a head mounted on a plaque on a papered wall, a picture frame beside it that
  must stay; the cameras stand in front of the wall, so what lies behind the plaque no view sees.

Every family returns a SceneSpec: the objects with their mask ids, and where the cameras orbit.
Environment pieces (floor, table, mats, slab, dome) carry id 0, the background.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from dataclasses import dataclass, field

import bpy
from mathutils import Vector

from scenegen import environment, materials
from scenegen.meshes import MeshBuilder


@dataclass
class SceneSpec:
    objects: list[tuple[bpy.types.Object, bool]] = field(default_factory=list)  # (object, is target)
    focus: Vector = field(default_factory=Vector)  # orbit centre
    distance: float = 1.0  # camera distance from the focus
    elevation: tuple[float, float] = (20.0, 40.0)  # degrees above the focus
    arc: float = 360.0  # degrees of azimuth the cameras span ('360' orbit): less for a wall they stand before
    facing: float = 0.0  # the arc's middle azimuth, radians (the x axis is 0)

    def add(self, builder: MeshBuilder, name: str, target: bool = False) -> bpy.types.Object:
        obj = builder.finish(name, pass_index=len(self.objects) + 1)
        self.objects.append((obj, target))
        return obj

    @property
    def target(self) -> bpy.types.Object:
        return next(obj for obj, target in self.objects if target)


def _table(rng: random.Random, width: float, depth: float, height: float, material) -> None:
    builder = MeshBuilder()
    builder.box((width, depth, 0.04), (0, 0, height - 0.02), material)
    for sx in (-1, 1):
        for sy in (-1, 1):
            builder.box((0.05, 0.05, height - 0.04), (sx * (width / 2 - 0.06), sy * (depth / 2 - 0.06),
                                                      (height - 0.04) / 2), material)
    builder.finish("table")


def tabletop(rng: random.Random) -> SceneSpec:
    spec = SceneSpec(distance=rng.uniform(0.75, 0.9), elevation=(25.0, 50.0))
    environment.add_floor(materials.checker(rng, "floor", (0.5, 0.5, 0.48), (0.3, 0.28, 0.26)))
    top = 0.75
    _table(rng, 1.3, 0.85, top, materials.wood(rng))
    toy_at = Vector((rng.uniform(-0.08, 0.08), rng.uniform(-0.05, 0.05), top))
    mats = MeshBuilder()  # two overlapping mats: the hole spans both textures
    angle = rng.uniform(-0.4, 0.4)
    mats.box((0.42, 0.3, 0.004), toy_at + Vector((-0.06, 0.02, 0.002)),
             materials.weave(rng, "mat_grey", (0.45, 0.45, 0.47), (0.25, 0.25, 0.27)), rotation=(0, 0, angle))
    mats.box((0.36, 0.28, 0.004), toy_at + Vector((0.07, -0.03, 0.0055)),
             materials.checker(rng, "mat_pink", (0.85, 0.6, 0.62), (0.7, 0.45, 0.5)),
             rotation=(0, 0, angle + rng.uniform(0.2, 0.6)))
    mats.finish("mats")
    z = top + 0.0075
    toy = MeshBuilder()
    yellow = materials.mottled(rng, "toy_yellow", (0.9, 0.7, 0.05), (0.7, 0.5, 0.02), scale=30)
    black = materials.mottled(rng, "toy_black", (0.05, 0.05, 0.05), (0.15, 0.15, 0.15), scale=60)
    length, width = rng.uniform(0.12, 0.16), rng.uniform(0.07, 0.09)
    yaw = rng.uniform(0, math.pi)
    rot = (0, 0, yaw)

    def at(dx: float, dy: float, dz: float) -> Vector:
        return toy_at + Vector((dx * math.cos(yaw) - dy * math.sin(yaw), dx * math.sin(yaw) + dy * math.cos(yaw),
                                z - top + dz))

    for side in (-1, 1):  # treads
        toy.box((length, 0.02, 0.03), at(0, side * width / 2, 0.015), black, rotation=rot)
    toy.box((length * 0.8, width * 0.8, 0.04), at(0, 0, 0.05), yellow, rotation=rot)
    toy.box((length * 0.35, width * 0.6, 0.045), at(-length * 0.15, 0, 0.092), yellow, rotation=rot)
    toy.box((0.02, width * 1.1, 0.035), at(length * 0.62, 0, 0.025), black, rotation=rot)  # bucket
    toy.cylinder(0.008, length * 0.5, at(length * 0.35, 0, 0.06), black, rotation=(0, math.radians(70), yaw))
    spec.add(toy, "toy", target=True)
    taken = [toy_at]
    for name, radius in (("mug", rng.uniform(0.03, 0.04)), ("ball", rng.uniform(0.025, 0.035))):
        place = _free_spot(rng, taken, 0.22, 0.5, 0.3)
        taken.append(place)
        b = MeshBuilder()
        if name == "mug":
            b.cylinder(radius, 0.09, place + Vector((0, 0, 0.045)),
                       materials.checker(rng, "mug", (0.2, 0.35, 0.7), (0.9, 0.9, 0.9)))
        else:
            b.sphere(radius, place + Vector((0, 0, radius)),
                     materials.mottled(rng, "ball", (0.8, 0.15, 0.1), (0.95, 0.8, 0.2), scale=15))
        spec.add(b, name)
    spec.focus = toy_at + Vector((0, 0, 0.05))
    return spec


def statue(rng: random.Random) -> SceneSpec:
    spec = SceneSpec(distance=rng.uniform(1.0, 1.2), elevation=(15.0, 40.0))
    environment.add_floor(materials.mottled(rng, "forest_floor", (0.22, 0.17, 0.1), (0.2, 0.3, 0.12), scale=6))
    slab = MeshBuilder()
    slab.box((rng.uniform(0.85, 1.0), rng.uniform(0.65, 0.8), 0.08), (0, 0, 0.04), materials.stone(rng, "slab"),
             rotation=(0, 0, rng.uniform(-0.3, 0.3)))
    slab.finish("slab")
    grey = materials.stone(rng, "statue_stone", (0.6, 0.6, 0.58))
    s = MeshBuilder()
    s.box((0.2, 0.2, 0.12), (0, 0, 0.14), grey)  # plinth
    body = rng.uniform(0.07, 0.09)
    s.sphere(body, (0, 0, 0.2 + body), grey, scale=(1.0, 0.8, 1.15), bumpiness=0.08, seed=rng.random() * 10)
    s.sphere(body * 0.6, (0, -body * 0.2, 0.2 + 2.4 * body), grey, bumpiness=0.05, seed=rng.random() * 10)
    for side in (-1, 1):
        s.sphere(body * 0.18, (side * body * 0.4, -body * 0.2, 0.2 + 2.95 * body), grey)
    spec.add(s, "statue", target=True)
    keep = MeshBuilder()  # the small white object on the slab that must stay
    keep.box((0.04, 0.03, 0.03), (rng.uniform(0.2, 0.32), rng.uniform(-0.2, 0.2), 0.095),
             materials.mottled(rng, "white_object", (0.92, 0.92, 0.9), (0.8, 0.8, 0.78), scale=40),
             rotation=(0, 0, rng.uniform(0, 3)))
    spec.add(keep, "white_object")
    for k in range(rng.randint(4, 6)):  # rocks and logs around the slab
        place = _ring_spot(rng, 0.6, 0.9)
        b = MeshBuilder()
        if k % 3 == 2:
            r = rng.uniform(0.03, 0.05)
            b.cylinder(r, rng.uniform(0.3, 0.5), place + Vector((0, 0, r)),
                       materials.wood(rng, "log"), rotation=(math.pi / 2, 0, rng.uniform(0, math.pi)))
            spec.add(b, f"log_{k}")
        else:
            r = rng.uniform(0.05, 0.1)
            b.sphere(r, place + Vector((0, 0, r * 0.5)), materials.stone(rng, "rock"), scale=(1, 0.8, 0.7),
                     bumpiness=0.25, seed=rng.random() * 10, segments=24)
            spec.add(b, f"rock_{k}")
    trunks = MeshBuilder()  # the woodland backdrop
    bark = materials.textured("bark", [(0.15, 0.08, 0.05), (0.35, 0.2, 0.12)],
                              [{"kind": "wave", "scale": 6.0, "distortion": 8.0}], roughness=0.9)
    for _ in range(rng.randint(5, 8)):
        place = _ring_spot(rng, 1.8, 3.5)
        trunks.cylinder(rng.uniform(0.15, 0.3), 5.0, place + Vector((0, 0, 2.5)), bark)
    trunks.finish("trees")
    spec.focus = Vector((0, 0, 0.22))
    return spec


def livingroom(rng: random.Random) -> SceneSpec:
    spec = SceneSpec(distance=rng.uniform(1.25, 1.4), elevation=(10.0, 32.0))
    environment.add_floor(materials.weave(rng, "carpet", (0.5, 0.35, 0.3), (0.35, 0.25, 0.22)))
    top = 0.45
    _table(rng, 1.4, 0.9, top, materials.wood(rng, "light_wood"))
    plush = MeshBuilder()  # large, white and fluffy: it hides the small objects from many views
    white = materials.mottled(rng, "plush_white", (0.93, 0.93, 0.9), (0.78, 0.78, 0.75), scale=60)
    r = rng.uniform(0.15, 0.18)
    plush.sphere(r, (0, 0, top + r * 0.95), white, scale=(1.0, 0.9, 1.0), bumpiness=0.06, seed=rng.random() * 10)
    plush.sphere(r * 0.65, (0, -r * 0.2, top + 2.3 * r), white, bumpiness=0.05, seed=rng.random() * 10)
    horn = materials.mottled(rng, "horn", (0.45, 0.3, 0.15), (0.3, 0.18, 0.08), scale=40)
    for side in (-1, 1):
        plush.cylinder(r * 0.12, r * 0.5, (side * r * 0.35, -r * 0.2, top + 2.95 * r), horn, radius_top=0.002,
                       rotation=(0, side * 0.4, 0))
    plush.sphere(r * 0.12, (0, -r * 0.78, top + 2.1 * r), materials.mottled(rng, "tongue", (0.9, 0.45, 0.5),
                                                                            (0.8, 0.3, 0.4)))
    spec.add(plush, "plush", target=True)
    base_angle = rng.uniform(0, 2 * math.pi)
    makers: list[Callable[[MeshBuilder, Vector], None]] = [
        lambda b, p: b.box((0.08, 0.07, 0.07), p + Vector((0, 0, 0.035)),
                           materials.checker(rng, "box", (0.05, 0.05, 0.05), (0.3, 0.3, 0.3)),
                           rotation=(0, 0, rng.uniform(0, 3))),
        lambda b, p: (b.sphere(0.042, p + Vector((0, 0, 0.04)),
                               materials.mottled(rng, "apple", (0.75, 0.08, 0.05), (0.9, 0.6, 0.1), 20)),
                      b.cylinder(0.004, 0.02, p + Vector((0, 0, 0.088)), horn)),
        lambda b, p: b.cylinder(0.024, 0.055, p + Vector((0, 0, 0.0275)),
                                materials.checker(rng, "sharpener", (0.1, 0.3, 0.8), (0.8, 0.8, 0.85))),
        lambda b, p: b.cylinder(0.03, 0.08, p + Vector((0, 0, 0.04)),
                                materials.mottled(rng, "cup", (0.2, 0.6, 0.3), (0.9, 0.9, 0.85), 25)),
    ]
    names = ["box", "apple", "sharpener", "cup"]
    for k, (name, make) in enumerate(zip(names, makers, strict=True)):
        angle = base_angle + k * math.pi / 2 + rng.uniform(-0.35, 0.35)
        dist = r + rng.uniform(0.06, 0.12)  # close behind or in front of the plush
        b = MeshBuilder()
        make(b, Vector((dist * math.cos(angle), dist * math.sin(angle), top)))
        spec.add(b, name)
    spec.focus = Vector((0, 0, top + 0.17))
    return spec


def wallmount(rng: random.Random) -> SceneSpec:
    """The wall is the plane y = 0 facing -y; the cameras sweep 150 degrees in front of it."""
    spec = SceneSpec(distance=rng.uniform(0.8, 0.95), elevation=(-12.0, 22.0), arc=150.0, facing=-math.pi / 2)
    environment.add_floor(materials.wood(rng, "parquet"))
    wall = MeshBuilder()
    paper = materials.textured("wallpaper", [materials.jitter(rng, (0.75, 0.7, 0.55)),
                                             materials.jitter(rng, (0.45, 0.5, 0.35))],
                               [{"kind": "wave", "scale": rng.uniform(8, 12), "distortion": 4.0},
                                {"kind": "noise", "scale": 40.0, "detail": 2.0}], roughness=0.8)
    wall.box((3.2, 0.06, 2.8), (0, 0.03, 1.4), paper)
    wall.finish("wall")
    height, x0 = rng.uniform(1.15, 1.35), rng.uniform(-0.1, 0.1)
    mount = MeshBuilder()
    plaque = materials.wood(rng, "plaque")
    mount.box((0.24, 0.03, 0.3), (x0, -0.015, height), plaque)
    fur = materials.mottled(rng, "fur", (0.55, 0.4, 0.25), (0.35, 0.25, 0.15), scale=50)
    r = rng.uniform(0.08, 0.095)
    mount.sphere(r, (x0, -0.03 - 0.8 * r, height + 0.01), fur, scale=(1.0, 1.25, 1.0), bumpiness=0.06,
                 seed=rng.random() * 10)
    mount.sphere(r * 0.5, (x0, -0.03 - 2.0 * r, height - 0.2 * r), fur, bumpiness=0.04, seed=rng.random() * 10)
    horn = materials.mottled(rng, "antler", (0.85, 0.8, 0.7), (0.6, 0.55, 0.45), scale=30)
    for side in (-1, 1):
        mount.cylinder(r * 0.12, r * 1.3, (x0 + side * r * 0.6, -0.03 - 0.7 * r, height + 1.3 * r), horn,
                       radius_top=0.003, rotation=(0, side * 0.5, 0))
    spec.add(mount, "trophy", target=True)
    frame = MeshBuilder()  # a picture beside it that must stay
    side = rng.choice((-1, 1))
    frame.box((0.28, 0.02, 0.2), (x0 + side * rng.uniform(0.42, 0.5), -0.01, height + rng.uniform(-0.05, 0.08)),
              materials.checker(rng, "picture", (0.2, 0.3, 0.6), (0.85, 0.8, 0.7)))
    spec.add(frame, "picture")
    basket = MeshBuilder()
    basket.cylinder(0.12, 0.25, (x0 - side * 0.35, -0.3, 0.125), materials.weave(rng, "basket", (0.6, 0.45, 0.25),
                                                                                   (0.4, 0.3, 0.15)))
    spec.add(basket, "basket")
    spec.focus = Vector((x0, -0.08, height))
    return spec


FAMILIES: dict[str, Callable[[random.Random], SceneSpec]] = {
    "tabletop": tabletop, "statue": statue, "livingroom": livingroom, "wallmount": wallmount,
}


def _ring_spot(rng: random.Random, r_min: float, r_max: float) -> Vector:
    angle, radius = rng.uniform(0, 2 * math.pi), rng.uniform(r_min, r_max)
    return Vector((radius * math.cos(angle), radius * math.sin(angle), 0.0))


def _free_spot(rng: random.Random, taken: list[Vector], min_dist: float, half_x: float, half_y: float) -> Vector:
    """A spot on the table top (|x| < half_x, |y| < half_y) at least `min_dist` from every taken spot."""
    for _ in range(500):
        p = Vector((rng.uniform(-half_x, half_x), rng.uniform(-half_y, half_y), taken[0].z))
        if all((p.xy - q.xy).length >= min_dist for q in taken):
            return p
    raise RuntimeError("no free spot on the table: the layout is too crowded for this seed")
