"""The add-on's operators on a tiny scene, headless: import a trained run, Remove Selected through the
engine (on the CPU, synchronously as under `blender -b`), the turntable script's frames and the Turntable
operator's MP4."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import bpy
import numpy as np
import pytest

from addon.engine_call import run_engine

pytestmark = pytest.mark.slow  # each runs the engine on a generated scene or a trained run
REPO = Path(__file__).resolve().parents[2]
ENGINE_PYTHON = REPO / ".venv" / "bin" / "python"


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> Path:
    """A tiny livingroom scene and a short CPU training run of it, both made by the real tools."""
    spec = importlib.util.spec_from_file_location("tests_conftest", REPO / "tests" / "conftest.py")
    shared = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(shared)  # the engine tests' make_scene: the real generator, tiny sizes
    os.environ["SPLATFILL_ENGINE_PYTHON"] = str(ENGINE_PYTHON)
    root = tmp_path_factory.mktemp("operators")
    shared.make_scene(root / "scene", "livingroom", env={"SPLATFILL_ENGINE_PYTHON": str(ENGINE_PYTHON)})
    run_engine(["train", "--scene", str(root / "scene"), "--out", str(root / "run"), "--preset", "tiny", "--steps",
                "300", "--device", "cpu"])
    return root / "run"


def _vertices(collection: bpy.types.Collection) -> int:
    return sum(len(o.data.vertices) for o in collection.objects)


def test_remove_selected_runs_the_engine_and_imports_the_scene_without_the_object(run: Path, registered):
    before_ply = (run / "point_cloud.ply").stat().st_mtime_ns
    assert bpy.ops.splatfill.import_splats(filepath=str(run / "point_cloud.ply")) == {"FINISHED"}
    original = bpy.data.collections[run.name]
    assert {"background", "plush", "box", "cup"} <= set(original.objects.keys())  # the Outliner lists the objects
    counts = {o.name: len(o.data.vertices) for o in original.objects}
    bpy.context.view_layer.objects.active = original.objects["plush"]
    assert bpy.ops.splatfill.remove_selected() == {"FINISHED"}
    result = bpy.data.collections[f"{run.name} without plush"]
    removed = Path(result["splatfill_removed"])
    report = json.loads((removed / "removal.json").read_text())
    assert removed.parent == run and report["object"]["name"] == "plush" and report["removed"] > 0
    assert _vertices(result) == report["gaussians_after"] == _vertices(original) - report["removed"] + report["laid"]
    assert {o.name: len(o.data.vertices) for o in original.objects} == counts  # the original is untouched
    assert (run / "point_cloud.ply").stat().st_mtime_ns == before_ply
    bpy.context.view_layer.objects.active = result.objects[0]
    assert bpy.ops.splatfill.evaluate() == {"FINISHED"}  # the removal's renders scored by the engine
    # Export Splats: the removed scene (its own stamped folder) as .spz, read back by the import
    assert bpy.ops.splatfill.export(filepath=str(run / "exports" / "without.ply"), format="spz") == {"FINISHED"}
    assert bpy.ops.splatfill.import_splats(filepath=str(run / "exports" / "without.spz")) == {"FINISHED"}
    assert _vertices(bpy.data.collections["exports"]) == report["gaussians_after"]


def test_clean_up_deletes_faint_gaussians_into_a_new_run_and_runs_again(run: Path, registered):
    """Clean Up twice in a row on the same run: two new runs (nothing written over), each without the faint
    Gaussians, shown in place of the original collection."""
    assert bpy.ops.splatfill.import_splats(filepath=str(run / "point_cloud.ply")) == {"FINISHED"}
    original = bpy.data.collections[run.name]
    bpy.context.view_layer.objects.active = original.objects[0]
    before = set(run.parent.glob(f"{run.name}-clean-*"))
    for around in (False, True):  # the second also deletes what holds a camera of the run's scene
        bpy.context.view_layer.objects.active = original.objects[0]
        assert bpy.ops.splatfill.clean_up(min_opacity=0.5, around_cameras=around) == {"FINISHED"}
    made = sorted(set(run.parent.glob(f"{run.name}-clean-*")) - before)
    assert len(made) == 2 and original.hide_viewport
    report = json.loads((made[0] / "clean.json").read_text())
    assert 0 < report["deleted"] < report["before"] and report["by_rule"]["opacity"] == report["deleted"]
    assert "around_cameras" in json.loads((made[1] / "clean.json").read_text())["by_rule"]
    assert _vertices(bpy.data.collections[made[0].name]) == report["before"] - report["deleted"]


def test_remove_selected_without_a_proxy_says_what_to_select(registered):
    with pytest.raises(RuntimeError, match="select one of a splatfill scene's objects"):
        bpy.ops.splatfill.remove_selected()


def test_turntable_writes_side_by_side_frames_and_an_mp4_that_decodes(run: Path, tmp_path: Path):
    removed = run / "removed-turntable"
    run_engine(["remove", "--run", str(run), "--object", "plush", "--out", str(removed), "--device", "cpu"])
    env = {**os.environ, "SPLATFILL_ENGINE_PYTHON": str(ENGINE_PYTHON)}
    proc = subprocess.run([sys.executable, str(REPO / "scripts" / "turntable.py"), "--run", str(run), "--removed",
                           str(removed), "--frames", "3", "--keep-frames", "--out", str(tmp_path / "tt"), "--device",
                           "cpu"], capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert _decoded(tmp_path / "tt" / "turntable.mp4") == ["3", str(2 * 96)]  # three frames, before | after
    frames = sorted((tmp_path / "tt" / "frames").glob("*.png"))
    assert [f.name for f in frames] == ["0000.png", "0001.png", "0002.png"]
    cameras = json.loads((tmp_path / "tt" / "cameras.json").read_text())
    assert len(cameras) == 3 and cameras[0]["width"] == 96
    image = bpy.data.images.load(str(frames[0]))
    assert tuple(image.size)[0] == 2 * 96  # before | after


def test_import_colmap_makes_a_camera_per_view_through_the_engine(run: Path, registered):
    scene = Path(json.loads((run / "config.json").read_text())["scene"])
    assert bpy.ops.splatfill.import_colmap(directory=str(scene)) == {"FINISHED"}
    cameras = bpy.data.collections[f"{scene.name} cameras"].objects
    assert len(cameras) == 8 and all(o.type == "CAMERA" for o in cameras)
    assert (bpy.context.scene.render.resolution_x, bpy.context.scene.render.resolution_y) == (96, 72)


def test_turntable_follows_a_blender_camera_path(run: Path, registered, tmp_path: Path):
    """--camera: a Blender camera's path over the frame range; here an imported COLMAP camera, so the path's
    one record must give back that view's intrinsics and pose."""
    sys.path.insert(0, str(REPO / "scripts"))
    import turntable

    scene_dir = Path(json.loads((run / "config.json").read_text())["scene"])
    assert bpy.ops.splatfill.import_colmap(directory=str(scene_dir)) == {"FINISHED"}
    camera = bpy.data.objects["0000"]
    bpy.context.scene.frame_start = bpy.context.scene.frame_end = 1
    removed = run / "removed-turntable"  # made by test_turntable_writes_side_by_side_frames_and_an_mp4_that_decodes
    if not removed.exists():
        run_engine(["remove", "--run", str(run), "--object", "plush", "--out", str(removed), "--device", "cpu"])
    assert turntable.main(["turntable.py", "--run", str(run), "--removed", str(removed), "--camera", camera.name,
                           "--out", str(tmp_path / "tt"), "--device", "cpu"]) == 0
    record = json.loads((tmp_path / "tt" / "cameras.json").read_text())[0]
    engine_cameras = tmp_path / "cameras.json"
    run_engine(["cameras", "--scene", str(scene_dir), "--out", str(engine_cameras)])
    truth = next(c for c in json.loads(engine_cameras.read_text()) if c["name"] == "0000.png")
    for key in ("width", "height", "fx", "fy", "cx", "cy"):
        assert record[key] == pytest.approx(truth[key], abs=1e-3)
    assert np.allclose(record["R"], truth["R"], atol=1e-5) and np.allclose(record["t"], truth["t"], atol=1e-4)
    assert (tmp_path / "tt" / "turntable.mp4").is_file() and not (tmp_path / "tt" / "frames").exists()


def _decoded(video: Path) -> list[str]:
    decode = ("import cv2, sys; c = cv2.VideoCapture(sys.argv[1]); n = 0\nwhile c.read()[0]: n += 1\n"
              "print(n, int(c.get(cv2.CAP_PROP_FRAME_WIDTH)))")  # decoded in the engine's Python, which has OpenCV
    return subprocess.run([str(ENGINE_PYTHON), "-c", decode, str(video)], capture_output=True, text=True,
                          check=True).stdout.split()


def test_the_turntable_operator_writes_an_mp4_of_an_orbit_or_of_the_scene_camera(run: Path, registered):
    """The add-on's Turntable: the same engine command as the script, on the active removed scene's collection."""
    removed = run / "removed-turntable"
    if not removed.exists():
        run_engine(["remove", "--run", str(run), "--object", "plush", "--out", str(removed), "--device", "cpu"])
    collection = bpy.data.collections.new("removed for the turntable")
    bpy.context.scene.collection.children.link(collection)
    collection["splatfill_run"], collection["splatfill_removed"] = str(run), str(removed)
    layer = bpy.context.view_layer.layer_collection.children[collection.name]
    bpy.context.view_layer.active_layer_collection = layer
    bpy.context.view_layer.objects.active = None
    before = set(run.glob("turntable-*"))
    assert bpy.ops.splatfill.turntable(frames=3) == {"FINISHED"}
    (orbit,) = set(run.glob("turntable-*")) - before
    assert _decoded(orbit / "turntable.mp4") == ["3", str(2 * 96)] and not (orbit / "frames").exists()
    scene_dir = Path(json.loads((run / "config.json").read_text())["scene"])
    assert bpy.ops.splatfill.import_colmap(directory=str(scene_dir)) == {"FINISHED"}
    bpy.context.scene.camera = bpy.data.objects["0001"]
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = 1, 2
    bpy.context.view_layer.active_layer_collection = layer
    bpy.context.view_layer.objects.active = None
    assert bpy.ops.splatfill.turntable(follow_camera=True) == {"FINISHED"}
    (path,) = set(run.glob("turntable-*")) - before - {orbit}
    assert _decoded(path / "turntable.mp4")[0] == "2" and len(json.loads((path / "cameras.json").read_text())) == 2
    # a completed scene's collection (as Complete leaves it): after is that scene, not the unfilled removal. Here the
    # "completion" is the original run itself, so the two halves of each frame agree
    done = bpy.data.collections.new("completed for the turntable")
    bpy.context.scene.collection.children.link(done)
    done["splatfill_run"], done["splatfill_scores"] = str(run), str(run / "scores.json")
    done["splatfill_original"], done["splatfill_completed_from"] = str(run), str(removed)
    bpy.context.view_layer.active_layer_collection = bpy.context.view_layer.layer_collection.children[done.name]
    assert bpy.ops.splatfill.turntable(frames=2) == {"FINISHED"}
    (completed,) = set(run.glob("turntable-*")) - before - {orbit, path}
    # below each half's label ("before", "after": different words, a quarter of a 96-pixel frame's rows)
    halves = ("import cv2, sys; ok, f = cv2.VideoCapture(sys.argv[1]).read(); w = f.shape[1] // 2\n"
              "f = f[f.shape[0] // 3:]; print(abs(f[:, :w].astype(int) - f[:, w:2 * w]).mean())")
    same = subprocess.run([str(ENGINE_PYTHON), "-c", halves, str(completed / "turntable.mp4")], capture_output=True,
                          text=True, check=True).stdout
    unfilled = subprocess.run([str(ENGINE_PYTHON), "-c", halves, str(orbit / "turntable.mp4")], capture_output=True,
                              text=True, check=True).stdout
    assert float(same) < 0.5 * float(unfilled), (same, unfilled)


def test_the_inpaint_and_complete_menus_list_the_engines_plugins(package, monkeypatch):
    """The menus come from the engine's registries (`python -m engine plugins`): every inpainter that fills
    a mask, and the completion methods that start from the Inpaint operator's output."""
    monkeypatch.setenv("SPLATFILL_ENGINE_PYTHON", str(ENGINE_PYTHON))
    pipeline = importlib.import_module(f"{package.__name__}.operators.pipeline")
    inpainters = {item[0] for item in pipeline._plugin_items("inpainters")}
    methods = {item[0] for item in pipeline._plugin_items("methods")}
    assert {"telea", "fsr", "exemplar", "lama"} <= inpainters and "nanobanana" not in inpainters
    assert methods == {"init", "ft", "reference"}  # direct reads `inpaint --source input`, which no operator writes
    # the defaults the tuning scenes chose come first (Blender preselects the first item), and the Complete menu
    # says why (engine.base.defaults)
    first_method, first_inpainter = pipeline._plugin_items("methods")[0], pipeline._plugin_items("inpainters")[0]
    assert (first_method[0], first_inpainter[0]) == ("reference", "coherence")
    assert "unfilled hole" in first_method[2]


def test_the_complete_operators_defaults_are_the_engines(package, registered, monkeypatch):
    """An option the Complete panel offers starts at the method's own default (`engine plugins`), the value the
    CLI and the benchmark use: FT's perceptual term was ST-LPIPS here and LPIPS in the CLI."""
    monkeypatch.setenv("SPLATFILL_ENGINE_PYTHON", str(ENGINE_PYTHON))
    engine_call = importlib.import_module(f"{package.__name__}.addon.engine_call")
    offered = bpy.ops.splatfill.complete.get_rna_type().properties  # what the panel's dialog starts from
    checked = 0
    for method in engine_call.engine_plugins(str(ENGINE_PYTHON))["methods"]:
        for option in method["options"]:
            if option["name"] in offered.keys():
                assert offered[option["name"]].default == option["default"], (method["name"], option)
                checked += 1
    assert checked >= 2  # refs and perceptual


def test_find_objects_and_object_from_selection_group_a_run_without_objects(run: Path, registered, tmp_path: Path):
    """A copy of the run stands for a capture: Find Objects from a mask folder, then a cube placed around
    part of the scene and then proxy points selected in Edit Mode each become one more named object."""
    import shutil

    copy = tmp_path / "capture-run"
    shutil.copytree(run, copy, ignore=shutil.ignore_patterns("checkpoints", "removed*"))
    scene = Path(json.loads((run / "config.json").read_text())["scene"])
    assert bpy.ops.splatfill.import_splats(filepath=str(copy / "point_cloud.ply")) == {"FINISHED"}
    bpy.context.view_layer.objects.active = bpy.data.collections[copy.name].objects[0]
    assert bpy.ops.splatfill.find_objects(masks=str(scene / "masks")) == {"FINISHED"}
    found = bpy.data.collections[f"{copy.name} objects"]
    entries = json.loads((copy / "segments" / "objects.json").read_text())
    assert {e["name"] for e in entries} <= set(found.objects.keys()) and entries

    box = entries[0]["box"]  # a cube around the first object's box, placed by hand in Blender
    bpy.ops.mesh.primitive_cube_add(location=[(box[i] + box[i + 3]) / 2 for i in range(3)])
    cube = bpy.context.active_object
    cube.scale = [(box[i + 3] - box[i]) / 2 for i in range(3)]
    bpy.context.view_layer.update()
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj == cube)
    bpy.context.view_layer.objects.active = found.objects[0]
    assert bpy.ops.splatfill.object_from_selection(name="boxed") == {"FINISHED"}
    assert "boxed" in {e["name"] for e in json.loads((copy / "segments" / "objects.json").read_text())}

    proxy = bpy.data.objects["boxed"]  # the latest import (each import makes a new collection)
    flags = np.zeros(len(proxy.data.vertices), bool)
    flags[:5] = True
    proxy.data.vertices.foreach_set("select", flags)
    index = np.zeros(len(proxy.data.vertices), np.int32)
    proxy.data.attributes["gaussian"].data.foreach_get("value", index)
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj == proxy)
    bpy.context.view_layer.objects.active = proxy
    assert bpy.ops.splatfill.object_from_selection(name="picked") == {"FINISHED"}
    ids = np.load(copy / "segments" / "ids.npy")
    picked = next(e for e in json.loads((copy / "segments" / "objects.json").read_text()) if e["name"] == "picked")
    assert picked["gaussians"] == 5 and set(ids[index[:5]]) == {picked["id"]}
    # Restore Objects undoes the last selection (Blender's Undo does not reach the engine's files); Find Objects
    # runs again, replacing what was found (kept for Restore)
    assert bpy.ops.splatfill.restore_objects() == {"FINISHED"}
    assert "picked" not in {e["name"] for e in json.loads((copy / "segments" / "objects.json").read_text())}
    assert bpy.ops.splatfill.find_objects(masks=str(scene / "masks")) == {"FINISHED"}
    assert "boxed" not in {e["name"] for e in json.loads((copy / "segments" / "objects.json").read_text())}


def test_a_cycles_render_of_the_imported_run_looks_like_the_engines_render(run: Path, tmp_path: Path):
    """benchmarks/blender_render.py on the tiny run's test view: the Gaussians drawn by addon.splat_shading
    (falloff, opacity, SH colour in linear light) come within a few dB of the rasterizer. The ico-sphere
    proxies they replace scored 11 dB on a tiny run; docs/BENCHMARKS.md has the measured numbers."""
    sys.path.insert(0, str(REPO / "benchmarks"))
    import blender_render

    result = blender_render.compare(run, run / "point_cloud.ply", [], tmp_path)
    assert result["mean_psnr"] >= 22.0, result
    assert (tmp_path / "side_by_side.png").is_file()


def test_one_gaussians_view_dependent_colour_in_blender_is_the_engines(tmp_path: Path):
    """One rotated, anisotropic, nearly opaque Gaussian with all 15 higher SH bands set, seen from three sides:
    the centre pixel of Blender's render (addon.splat_shading) equals the engine's within 2/255 per channel; a
    band read in the wrong order, a sign or the view direction not turned back into the splat's frame fails."""
    from addon.formats import splat_ply

    sys.path.insert(0, str(REPO / "benchmarks"))
    import blender_render

    os.environ["SPLATFILL_ENGINE_PYTHON"] = str(ENGINE_PYTHON)
    rng = np.random.default_rng(1)
    columns = {name: np.zeros(1) for name in splat_ply.property_names(15, with_identity=False)}
    columns.update({f"scale_{i}": np.log([[0.5, 0.3, 0.2][i]]) for i in range(3)}, opacity=np.array([8.0]))
    columns.update({f"rot_{i}": np.array([v]) for i, v in enumerate(np.array([0.9, 0.3, -0.2, 0.25]) / 1.0112)})
    columns.update({f"f_rest_{i}": rng.normal(0, 0.15, 1) for i in range(45)})
    splat_ply.write_vertices(tmp_path / "one.ply", columns)
    cameras = []
    for k, angle in enumerate([0.3, 2.0, 4.0]):
        centre = np.array([4 * np.cos(angle), 4 * np.sin(angle), 1.5 * (k - 1)])
        forward = -centre / np.linalg.norm(centre)
        right = np.cross(forward, [0, 0, 1]) / np.linalg.norm(np.cross(forward, [0, 0, 1]))
        R = np.stack([right, np.cross(forward, right), forward])
        cameras.append({"name": f"{k:04d}.png", "width": 32, "height": 32, "fx": 90.0, "fy": 90.0, "cx": 16.0,
                        "cy": 16.0, "R": R.tolist(), "t": (-R @ centre).tolist()})
    (tmp_path / "cameras.json").write_text(json.dumps(cameras))
    (tmp_path / "out").mkdir()
    blender_render.compare_cameras(tmp_path / "one.ply", tmp_path / "cameras.json", tmp_path / "out")
    seen = [blender_render.read_rgb(tmp_path / "out" / side / "0000.png")[16, 16] for side in ("engine", "blender")]
    for camera in cameras:
        engine, blender = (blender_render.read_rgb(tmp_path / "out" / side / camera["name"])[16, 16]
                           for side in ("engine", "blender"))
        assert np.abs(engine - blender).max() <= 2.5 / 255, (camera["name"], engine, blender)
    assert np.abs(seen[0] - blender_render.read_rgb(tmp_path / "out" / "engine" / "0001.png")[16, 16]).max() > 0.05
