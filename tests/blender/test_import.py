"""Importing into Blender: cameras that project like COLMAP's, splats as one proxy object per identity."""

from __future__ import annotations

import json
from pathlib import Path

import bpy
import numpy as np
import pytest
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

from addon.formats import cameras as camera_formats
from addon.formats import splat_ply
from addon.import_scene import import_cameras, import_splats
from addon.splat_ply import read_splats
from addon.splat_shading import extents
from engine.base.errors import InputError

# landscape, portrait, fx != fy, and principal points off centre: the cases a 36 mm shortcut gets wrong
INTRINSICS = [(640, 480, 500.0, 500.0, 320.0, 240.0), (480, 640, 520.0, 520.0, 250.0, 300.0),
              (640, 480, 600.0, 540.0, 300.5, 260.0), (300, 500, 410.0, 455.0, 140.0, 270.0)]


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    return q * np.sign(np.linalg.det(q))


def test_imported_cameras_project_known_points_like_colmap(tmp_path: Path):
    rng = np.random.default_rng(0)
    records = []
    for k, (w, h, fx, fy, cx, cy) in enumerate(INTRINSICS):
        R = _rotation(rng)
        records.append({"name": f"{k:04d}.png", "width": w, "height": h, "fx": fx, "fy": fy, "cx": cx, "cy": cy,
                        "R": R.tolist(), "t": (rng.normal(size=3) + [0, 0, 6]).tolist()})
    collection = bpy.data.collections.new("cameras")
    bpy.context.scene.collection.children.link(collection)
    (tmp_path / "cameras.json").write_text(json.dumps(records))
    cameras = import_cameras(tmp_path / "cameras.json", collection)
    scene = bpy.context.scene
    worst = 0.0
    for r, obj in zip(records, cameras, strict=True):
        scene.render.resolution_x, scene.render.resolution_y = obj["splatfill_resolution"]
        scene.render.pixel_aspect_x, scene.render.pixel_aspect_y = obj["splatfill_pixel_aspect"]
        R, t = np.array(r["R"]), np.array(r["t"])
        cam_points = rng.uniform([-1, -1, 3], [1, 1, 9], size=(20, 3))  # in front of the camera
        world = (cam_points - t) @ R
        for p_cam, p_world in zip(cam_points, world, strict=True):
            u = r["fx"] * p_cam[0] / p_cam[2] + r["cx"]
            v = r["fy"] * p_cam[1] / p_cam[2] + r["cy"]
            ndc = world_to_camera_view(scene, obj, Vector(p_world))
            worst = max(worst, abs(ndc.x * r["width"] - u), abs((1 - ndc.y) * r["height"] - v))
        back = camera_formats.colmap_record(r["name"], np.array(obj.matrix_world), obj.data.lens, obj.data.sensor_width,
                             obj.data.sensor_height, obj.data.sensor_fit, obj.data.shift_x, obj.data.shift_y,
                             r["width"], r["height"], tuple(obj["splatfill_pixel_aspect"]))
        for key in ("fx", "fy", "cx", "cy"):
            assert back[key] == pytest.approx(r[key], abs=1e-3)
        assert np.allclose(back["R"], R, atol=1e-5) and np.allclose(back["t"], t, atol=1e-4)
    assert worst < 0.5, f"worst reprojection error {worst:.3f} px"


def write_splat_ply(path: Path, positions: np.ndarray, identity: np.ndarray) -> None:
    """A 3DGS .ply written with the numpy writer Blender shares with the engine: degree-0 SH and identities."""
    n = len(positions)
    columns = {name: np.zeros(n, np.float32) for name in splat_ply.property_names(0, with_identity=True)}
    for i, axis in enumerate("xyz"):
        columns[axis] = positions[:, i]
    columns["f_dc_0"][:], columns["opacity"][:], columns["rot_0"][:] = 1.0, 2.0, 1.0
    for i in range(3):
        columns[f"scale_{i}"][:] = np.log(0.01)
    for i in range(splat_ply.IDENTITY_DIM):
        columns[f"obj_dc_{i}"] = identity[:, i]
    path.parent.mkdir(parents=True, exist_ok=True)
    splat_ply.write_vertices(path, columns)


def fake_run(root: Path, counts: dict[int, int]) -> Path:
    """A run folder as the engine leaves it: point_cloud.ply, classifier.npz, config.json naming a scene
    whose masks/objects.json names the objects. Identities are one-hot in the first dimensions."""
    groups = np.repeat(list(counts), list(counts.values()))
    identity = np.zeros((len(groups), 16), np.float32)
    identity[np.arange(len(groups)), groups] = 1.0
    rng = np.random.default_rng(0)
    write_splat_ply(root / "point_cloud.ply", rng.normal(size=(len(groups), 3)), identity)
    weight = np.zeros((4, 16), np.float32)
    weight[np.arange(4), np.arange(4)] = 5.0
    np.savez(root / "classifier.npz", weight=weight, bias=np.zeros(4, np.float32))
    (root / "scene" / "masks").mkdir(parents=True)
    (root / "scene" / "masks" / "objects.json").write_text(json.dumps(
        [{"id": 1, "name": "sofa", "target": False}, {"id": 2, "name": "plush", "target": True}]))
    (root / "config.json").write_text(json.dumps({"scene": str(root / "scene")}))
    return root / "point_cloud.ply"


def test_ply_import_makes_one_proxy_object_per_identity_with_its_gaussians(tmp_path: Path):
    ply = fake_run(tmp_path, {0: 500, 1: 300, 2: 120, 3: 7})
    collection = bpy.data.collections.new("run")
    bpy.context.scene.collection.children.link(collection)
    objects = import_splats(ply, collection)
    counts = {o.name: len(o.data.vertices) for o in objects}
    assert counts == {"background": 500, "sofa": 300, "plush": 120, "object_3": 7}
    plush = bpy.data.objects["plush"]
    assert plush["splatfill_group"] == 2 and plush.modifiers[0].node_group.name == "splatfill splats"
    evaluated = plush.evaluated_get(bpy.context.evaluated_depsgraph_get())
    assert len(evaluated.evaluated_geometry().instances_pointcloud().points) == 120  # unrealized instances
    scale = np.zeros(120 * 3, np.float32)
    plush.data.attributes["scale"].data.foreach_get("vector", scale)
    opacity = 1 / (1 + np.exp(-np.array([2.0])))  # the fake run's opacity logit
    assert np.allclose(scale, 0.01 * extents(opacity)[0])  # the instance reaches the Gaussian's drawn extent
    assert 2.9 < extents(opacity)[0] < 3.0 and extents(np.array([0.5 / 255]))[0] == 0


def test_corrupt_ply_names_the_file(tmp_path: Path):
    bad = tmp_path / "broken.ply"
    bad.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty float x\nend_header\n")
    with pytest.raises(InputError, match="broken.ply"):
        read_splats(bad)


def _quat(R: np.ndarray) -> np.ndarray:
    """w, x, y, z of a rotation matrix (the trace branch is enough for the rotations used here)."""
    w = np.sqrt(max(1e-12, 1 + np.trace(R))) / 2
    return np.array([w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)])


def test_a_tilted_capture_is_imported_upright_and_gives_back_its_cameras(tmp_path: Path):
    """SfM chose its own axes (here 121 degrees off): the cameras come in under an upright frame whose world
    up is the cameras' mean up, while each camera still converts back to exactly its COLMAP pose."""
    from addon.import_scene import engine_matrix
    from engine.formats.cameras import Camera, write_cameras_json

    axis = np.array([1.0, 0.3, 0.2]) / np.linalg.norm([1.0, 0.3, 0.2])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    angle = np.radians(121)
    Q = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    cameras, lines = [], []
    for i in range(8):
        centre = np.array([3 * np.cos(i * np.pi / 4), 3 * np.sin(i * np.pi / 4), 1.0])
        forward = -centre / np.linalg.norm(centre)
        right = np.cross(forward, [0, 0, 1])
        right /= np.linalg.norm(right)
        R = np.stack([right, np.cross(forward, right), forward]) @ Q.T  # the same rig, in SfM's tilted world
        t = -R @ (Q @ centre)
        cameras.append(Camera(f"{i:04d}.png", 64, 48, 50.0, 50.0, 32.0, 24.0, R, t))
        lines += [f"{i + 1} {' '.join(map(str, _quat(R)))} {' '.join(map(str, t))} 1 {i:04d}.png", ""]
    model = tmp_path / "scene" / "sparse" / "0"
    model.mkdir(parents=True)
    (model / "cameras.txt").write_text("1 PINHOLE 64 48 50 50 32 24\n")
    (model / "images.txt").write_text("\n".join(lines) + "\n")
    (model / "points3D.txt").write_text("")
    write_cameras_json(cameras, tmp_path / "cameras.json")
    collection = bpy.data.collections.new("capture")
    bpy.context.scene.collection.children.link(collection)
    objects = import_cameras(tmp_path / "cameras.json", collection, tmp_path / "scene")
    assert all(o.parent is not None and "splatfill_frame" in o.parent for o in objects)
    up = np.mean([np.array(o.matrix_world.col[1][:3]) for o in objects], axis=0)  # a Blender camera's +Y
    assert np.allclose(up / np.linalg.norm(up), [0, 0, 1], atol=1e-5)
    for obj, camera in zip(objects, cameras, strict=True):
        d = obj.data
        back = camera_formats.colmap_record(camera.name, engine_matrix(obj), d.lens, d.sensor_width, d.sensor_height,
                                            d.sensor_fit, d.shift_x, d.shift_y, 64, 48)
        assert np.allclose(back["R"], camera.R, atol=1e-5) and np.allclose(back["t"], camera.t, atol=1e-4)
