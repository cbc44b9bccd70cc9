"""The pipeline as Blender operators: import, Train / Group, Remove Selected, Hole Masks, Inpaint, Complete,
Evaluate, Turntable.

Each is thin: it reads the selection and its properties, names a new output folder (never over an input),
runs one engine command through EngineOperator, and imports what the engine wrote into a new collection
beside the original, which stays untouched. The run a proxy belongs to travels as custom properties on its
collection: splatfill_run (the training run), and for later stages splatfill_removed, splatfill_holes,
splatfill_inpainted.
"""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path

import bpy

from ..addon.camera_path import camera_path
from ..addon.engine_call import EngineError, engine_plugins
from ..addon.formats import InputError, layout
from ..addon.import_scene import import_cameras, import_splats
from .engine_operator import EngineOperator, UserError, done_record, engine_settings

_ITEMS: dict[str, list[tuple[str, str, str]]] = {}  # Blender needs the enum strings kept alive


def _plugin_items(kind: str) -> list[tuple[str, str, str]]:
    """Menu items from the engine's registry: inpainters, or the completion methods that start from the
    Inpaint operator's output (the removed renders' holes)."""
    if kind not in _ITEMS:
        try:
            plugins = engine_plugins(engine_settings().python)
        except EngineError as exc:
            return [("", "engine unavailable", str(exc))]
        defaults = plugins.get("defaults", {})
        if kind == "inpainters":
            items = [(i["name"], i["name"], f"{i['summary']} (needs: {i['needs']})")
                     for i in plugins["inpainters"] if i["uses_mask"]]
            first = defaults.get("inpainter")
        else:
            items = [(m["name"], m["label"], f"{m['summary']} (needs: {m['needs']})")
                     for m in plugins["methods"] if m["source"] == "removed"]
            first = defaults.get("method") or (defaults.get("best_on_mean") or [None])[0]
            items = [(n, label, f"{tip}. The default: {defaults['why']}" if n == first and defaults.get("why") else tip)
                     for n, label, tip in items]
        _ITEMS[kind] = sorted(items, key=lambda item: item[0] != first)  # Blender's default is the first item
    return _ITEMS[kind]


def _inpainter_items(self, context):
    return _plugin_items("inpainters")


def _method_items(self, context):
    return _plugin_items("methods")


def stamp() -> str:
    """A time to the millisecond for output folder names: an operator run twice on one run writes two folders."""
    now = time.time()
    return time.strftime("%Y%m%d-%H%M%S", time.localtime(now)) + f"-{int(now * 1000) % 1000:03d}"


def _new_collection(name: str, **props: str) -> bpy.types.Collection:
    collection = bpy.data.collections.new(name)
    bpy.context.scene.collection.children.link(collection)
    for key, value in props.items():
        collection[key] = value
    return collection


def _active_collection(context: bpy.types.Context, needs: str) -> bpy.types.Collection | None:
    """The active proxy's collection (or the active collection) carrying `needs`, or None."""
    obj = context.active_object
    candidates = [*(obj.users_collection if obj is not None else []), context.collection]
    return next((c for c in candidates if c is not None and needs in c), None)


def run_collection(context: bpy.types.Context, needs: str = "splatfill_run") -> bpy.types.Collection:
    """The collection of the active proxy (or the active collection), which must carry `needs`."""
    collection = _active_collection(context, needs)
    if collection is not None:
        return collection
    step = {"splatfill_run": "import or train a run", "splatfill_removed": "run Remove Selected",
            "splatfill_holes": "run Hole Masks", "splatfill_inpainted": "run Inpaint"}[needs]
    raise UserError(f"select a splatfill proxy whose collection has {needs}: {step} first")


def import_run_ply(ply: Path, name: str, **props: str) -> bpy.types.Collection:
    collection = _new_collection(name, **props)
    import_splats(ply, collection)
    return collection


class SPLATFILL_OT_import_colmap(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.import_colmap"
    bl_label = "Import COLMAP Cameras"
    bl_description = "Import a COLMAP scene folder's cameras (sparse/0) as Blender cameras"
    directory: bpy.props.StringProperty(subtype="DIR_PATH")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def engine_args(self, context, device):
        self._json = Path(tempfile.mkdtemp(prefix="splatfill-cameras-")) / "cameras.json"
        return ["cameras", "--scene", bpy.path.abspath(self.directory), "--out", str(self._json)]

    def finish(self, context, records):
        scene = Path(bpy.path.abspath(self.directory))
        cameras = import_cameras(self._json, _new_collection(f"{scene.name} cameras", splatfill_scene=str(scene)),
                                 scene)
        return f"imported {len(cameras)} cameras from {scene}"


class SPLATFILL_OT_import_splats(bpy.types.Operator):
    bl_idname = "splatfill.import_splats"
    bl_label = "Import Gaussian Splats"
    bl_description = ("Import a splat file (3DGS .ply, SuperSplat's compressed .ply, .splat or .spz) as "
                      "Gaussians (falloff, opacity, view-dependent colour), one object per identity group")
    bl_options = {"REGISTER", "UNDO"}
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    filter_glob: bpy.props.StringProperty(default="*.ply;*.splat;*.spz", options={"HIDDEN"})

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        from ..addon.formats import InputError

        ply = Path(bpy.path.abspath(self.filepath))
        run = {"splatfill_run": str(ply.parent)} if layout.RunLayout(ply.parent).config_json.is_file() else {}
        try:
            start = time.perf_counter()
            collection = import_run_ply(ply, ply.parent.name, **run)
        except InputError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, f"imported {len(collection.objects)} objects from {ply} in "
                              f"{time.perf_counter() - start:.1f} s")
        return {"FINISHED"}


class SPLATFILL_OT_train(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.train"
    bl_label = "Train / Group"
    bl_description = "Train a Gaussian Grouping scene on a scene folder in the engine, then import it"
    scene: bpy.props.StringProperty(name="Scene folder", subtype="DIR_PATH")
    out: bpy.props.StringProperty(name="Run folder", subtype="DIR_PATH", description="empty: beside the scene")
    steps: bpy.props.IntProperty(name="Steps", default=0, min=0, description="0: the preset's")
    preset: bpy.props.EnumProperty(name="Preset", items=[("default", "default", ""), ("tiny", "tiny", "")])

    def engine_args(self, context, device):
        scene = Path(bpy.path.abspath(self.scene))
        self._out = Path(bpy.path.abspath(self.out)) if self.out else scene.parent / f"{scene.name}-run-{stamp()}"
        args = ["train", "--scene", str(scene), "--out", str(self._out), "--preset", self.preset, "--device", device]
        return args + (["--steps", str(self.steps)] if self.steps else [])

    def finish(self, context, records):
        import_run_ply(layout.RunLayout(self._out).point_cloud, self._out.name, splatfill_run=str(self._out))
        return f"trained {self._out}"


class SPLATFILL_OT_remove_selected(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.remove_selected"
    bl_label = "Remove Selected"
    bl_description = "Remove the object selected in the Outliner from its run, in the engine; import the result"

    def engine_args(self, context, device):
        obj = context.active_object
        if obj is None or "splatfill_group" not in obj:
            raise UserError("select one of a splatfill scene's objects in the Outliner first")
        run = Path(run_collection(context)["splatfill_run"])
        self._name = obj.name
        self._run = run
        self._out = run / f"removed-{bpy.path.clean_name(obj.name)}-{stamp()}"
        return ["remove", "--run", str(run), "--object", str(obj["splatfill_group"]), "--out", str(self._out),
                "--device", device]

    def finish(self, context, records):
        done = done_record(records, "removal")
        import_run_ply(layout.RemovedLayout(self._out).point_cloud, f"{self._run.name} without {self._name}",
                       splatfill_run=str(self._run), splatfill_removed=str(self._out))
        return f"removed {done.get('removed')} Gaussians of {self._name}: {self._out}"


class SPLATFILL_OT_hole_masks(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.hole_masks"
    bl_label = "Hole Masks"
    bl_description = "Depth-guided masks of what no view saw behind the removed object"

    def engine_args(self, context, device):
        self._collection = run_collection(context, "splatfill_removed")
        removed = Path(self._collection["splatfill_removed"])
        self._out = removed.parent / f"holes-{removed.name}-{stamp()}"
        return ["holes", "--run", self._collection["splatfill_run"], "--removed", str(removed), "--out",
                str(self._out)]

    def finish(self, context, records):
        self._collection["splatfill_holes"] = str(self._out)
        iou = done_record(records, "holes").get("mean_iou_vs_truth")  # the masks that will be inpainted
        return f"hole masks in {self._out}" + (f" (IoU against the scene's holes {iou:.2f})" if iou else "")


class SPLATFILL_OT_inpaint(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.inpaint"
    bl_label = "Inpaint"
    bl_description = "Fill the hole masks of the removed renders in 2D (RGB and depth)"
    inpainter: bpy.props.EnumProperty(name="Inpainter", items=_inpainter_items)

    def engine_args(self, context, device):
        self._collection = run_collection(context, "splatfill_holes")
        removed = Path(self._collection["splatfill_removed"])
        self._out = removed.parent / f"inpainted-{self.inpainter}-{removed.name}-{stamp()}"
        return ["inpaint", "--run", self._collection["splatfill_run"], "--removed", str(removed), "--holes",
                self._collection["splatfill_holes"], "--inpainter", self.inpainter, "--out", str(self._out)]

    def finish(self, context, records):
        self._collection["splatfill_inpainted"] = str(self._out)
        self._collection["splatfill_inpainter"] = self.inpainter
        return f"inpainted views in {self._out}"


class SPLATFILL_OT_complete(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.complete"
    bl_label = "Complete"
    bl_description = ("Fill the hole in 3D from the inpainted views, score it, import the result. Optional: no "
                      "method beat leaving the hole unfilled on every held-out scene (docs/BENCHMARKS.md)")
    method: bpy.props.EnumProperty(name="Method", items=_method_items)
    refs: bpy.props.IntProperty(name="Reference views", default=3, min=0, description="FT: 0 = all")
    perceptual: bpy.props.EnumProperty(name="Perceptual term", default="st-lpips",
                                       items=[("lpips", "LPIPS", ""), ("st-lpips", "ST-LPIPS", ""), ("l1", "L1", "")])

    def engine_args(self, context, device):
        self._collection = c = run_collection(context, "splatfill_inpainted")
        removed = Path(c["splatfill_removed"])
        self._out = removed.parent / f"complete-{self.method}-{removed.name}-{stamp()}"
        method = next(m for m in engine_plugins(engine_settings().python)["methods"] if m["name"] == self.method)
        own = {o["name"] for o in method["options"]}  # only the chosen method's options reach the engine
        options = [arg for name in ("refs", "perceptual") if name in own
                   for arg in (f"--{name}", str(getattr(self, name)))]
        return ["complete", "--run", c["splatfill_run"], "--removed", str(removed), "--holes", c["splatfill_holes"],
                "--inpainted", c["splatfill_inpainted"], "--inpainter", c["splatfill_inpainter"], "--method",
                self.method, *options, "--out", str(self._out), "--device", device]

    def finish(self, context, records):
        done = done_record(records, "complete")
        out = layout.CompleteLayout(self._out)
        c = self._collection  # the turntable shows this scene against the one the removal started from
        import_run_ply(out.run.point_cloud, done["method"], splatfill_run=str(out.run.root),
                       splatfill_scores=str(out.scores_json), splatfill_original=c["splatfill_run"],
                       splatfill_completed_from=c["splatfill_removed"])
        return f"{done['method']}: m-PSNR {done.get('m_psnr')} dB, {self._out}"


class SPLATFILL_OT_evaluate(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.evaluate"
    bl_label = "Evaluate"
    bl_description = "PSNR, SSIM, LPIPS, FID and their masked variants on the test views of the active scene"

    def engine_args(self, context, device):
        c = run_collection(context)
        removed = ["--removed", c["splatfill_removed"]] if "splatfill_removed" in c else []
        self._name = c.name
        return ["evaluate", "--run", c["splatfill_run"], *removed, "--device", device]

    def finish(self, context, records):
        scores = done_record(records, "evaluate")["scores"]
        shown = [f"{k} {scores[k]:.3f}" for k in ("psnr", "m_psnr", "ssim", "m_ssim", "lpips", "m_lpips")
                 if scores.get(k) is not None]
        return f"{self._name}: " + ", ".join(shown)


class SPLATFILL_OT_turntable(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.turntable"
    bl_label = "Turntable"
    bl_description = ("Before | after around the removed object as an H.264 MP4, rendered by the engine (after: the "
                      "removed scene, or the completed one when a completion is active): an orbit, or the scene "
                      "camera's path over the frame range")
    frames: bpy.props.IntProperty(name="Frames", default=48, min=1, description="frames of the orbit")
    follow_camera: bpy.props.BoolProperty(name="Follow the scene camera", default=False,
                                          description="the scene camera's path over the frame range, not an orbit")

    def engine_args(self, context, device):
        completed = _active_collection(context, "splatfill_completed_from")
        if completed is not None:  # a completed scene: before the removal | after the completion
            run, removed = completed["splatfill_original"], Path(completed["splatfill_completed_from"])
            after = ["--after", str(layout.RunLayout(completed["splatfill_run"]).point_cloud)]
        else:  # a removed scene: before | the removal's, unfilled
            c = run_collection(context, "splatfill_removed")
            run, removed, after = c["splatfill_run"], Path(c["splatfill_removed"]), []
        self._out = removed.parent / f"turntable-{removed.name}-{stamp()}"
        args = ["turntable", "--run", run, "--removed", str(removed), *after, "--out", str(self._out),
                "--frames", str(self.frames), "--device", device]
        self._cameras = None
        if self.follow_camera:
            try:
                records = camera_path(context.scene.camera, context.scene)
            except InputError as exc:
                raise UserError(str(exc)) from exc
            with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="splatfill-cameras-", delete=False) as f:
                json.dump(records, f)
            self._cameras = Path(f.name)
            args += ["--cameras", f.name]
        return args

    def finish(self, context, records):
        if self._cameras is not None:
            self._cameras.unlink(missing_ok=True)
        done = done_record(records, "turntable")
        return f"turntable: {done['out']} ({done['frames']} frames)"


EXPORT_FORMATS = (("ply", "3DGS .ply", "the standard INRIA layout every splat tool reads", ".ply"),
                  ("compressed-ply", "Compressed .ply", "SuperSplat's, about a quarter of the size", ".compressed.ply"),
                  ("splat", ".splat", "antimatter15's web viewer layout (no view-dependent colour)", ".splat"),
                  ("spz", ".spz", "Niantic's compressed format", ".spz"))


class SPLATFILL_OT_export(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.export"
    bl_label = "Export Splats"
    bl_description = ("Write the active collection's scene (trained, removed or completed) as a splat file other "
                      "tools open: .ply, compressed .ply, .splat or .spz")
    bl_options = {"REGISTER"}  # writes a file, changes nothing in Blender: nothing to undo
    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    format: bpy.props.EnumProperty(name="Format", items=[f[:3] for f in EXPORT_FORMATS], default="ply")
    with_identities: bpy.props.BoolProperty(name="Keep identities", default=False,
                                            description=".ply: keep splatfill's 16 identity fields (only it reads "
                                                        "them)")

    def invoke(self, context, event):
        c = run_collection(context)
        self.filepath = str(Path(c["splatfill_run"]) / f"{bpy.path.clean_name(c.name)}.ply")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def engine_args(self, context, device):
        c = run_collection(context)
        suffix = next(f[3] for f in EXPORT_FORMATS if f[0] == self.format)
        out = Path(bpy.path.abspath(self.filepath))
        name = out.name.removesuffix(".compressed.ply").removesuffix(out.suffix) if out.suffix else out.name
        self._out = out.with_name(name + suffix)
        stage = ["--stage", c["splatfill_removed"]] if "splatfill_removed" in c else []
        identities = ["--with-identities"] if self.with_identities else []
        return ["export", "--run", c["splatfill_run"], *stage, "--format", self.format, "--out", str(self._out),
                *identities]

    def finish(self, context, records):
        done = done_record(records, "export")
        return f"exported {done['gaussians']} Gaussians as {done['format']}: {done['out']}"


CLASSES = (SPLATFILL_OT_import_colmap, SPLATFILL_OT_import_splats, SPLATFILL_OT_train,
           SPLATFILL_OT_remove_selected, SPLATFILL_OT_hole_masks, SPLATFILL_OT_inpaint, SPLATFILL_OT_complete,
           SPLATFILL_OT_evaluate, SPLATFILL_OT_turntable, SPLATFILL_OT_export)


register, unregister = bpy.utils.register_classes_factory(CLASSES)
