"""A user's own capture in Blender: Import Capture, Find Objects, Object from Selection.

Import Capture makes a run from a COLMAP folder (training it in the engine) or from a .ply trained elsewhere
plus that folder (`engine import-splat`, no training) and imports its proxies, upright. A capture has no
object masks, so the proxies are one background object until Find Objects (`engine segment --auto`, or
`--from-masks` with a folder of 2D masks) groups the Gaussians; Object from Selection turns the proxy points
selected in Edit Mode, or the bounds of a selected mesh (a cube placed around the object), into one more
object (`segment --indices` / `--box`). Each re-imports the run grouped by its objects into a new collection,
so Remove Selected and the rest of the pipeline work as on a generated scene.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import bpy
import numpy as np

from ..addon.formats import layout
from ..addon.import_scene import engine_matrix
from .engine_operator import EngineOperator, UserError, done_record
from .pipeline import import_run_ply, run_collection, stamp


class SPLATFILL_OT_import_capture(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.import_capture"
    bl_label = "Import Capture"
    bl_description = ("A COLMAP folder (trained in the engine), or a .ply trained elsewhere with its COLMAP "
                      "folder, as a run whose proxies Blender shows upright")
    directory: bpy.props.StringProperty(name="COLMAP folder", subtype="DIR_PATH")
    ply: bpy.props.StringProperty(name="Trained .ply", subtype="FILE_PATH", description="empty: train one")
    preset: bpy.props.EnumProperty(name="Preset", items=[("default", "default", ""), ("tiny", "tiny", "")])
    resolution: bpy.props.EnumProperty(name="Resolution", items=[(r, f"1/{r}", "") for r in ("1", "2", "4", "8")])

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def engine_args(self, context, device):
        scene = Path(bpy.path.abspath(self.directory))
        self._out = scene.parent / f"{scene.name}-run-{stamp()}"
        common = ["--scene", str(scene), "--out", str(self._out), "--resolution", self.resolution, "--device", device]
        if self.ply:
            return ["import-splat", "--ply", bpy.path.abspath(self.ply), *common]
        return ["train", "--preset", self.preset, *common]

    def finish(self, context, records):
        import_run_ply(layout.RunLayout(self._out).point_cloud, self._out.name, splatfill_run=str(self._out))
        return f"imported {self._out}: Find Objects groups it"


class _SegmentOperator(EngineOperator):
    """Runs `engine segment` on the active proxy's run and re-imports the run grouped by its objects."""

    def segment_args(self, context) -> list[str]:
        raise NotImplementedError

    def engine_args(self, context, device):
        self._run = Path(run_collection(context)["splatfill_run"])
        return ["segment", "--run", str(self._run), *self.segment_args(context), "--device", device]

    def finish(self, context, records):
        done = done_record(records, "segment")
        import_run_ply(layout.RunLayout(self._run).point_cloud, f"{self._run.name} objects",
                       splatfill_run=str(self._run))
        return f"{done['objects']} objects in {self._run.name}: select one in the Outliner to remove it"


class SPLATFILL_OT_find_objects(_SegmentOperator, bpy.types.Operator):
    bl_idname = "splatfill.find_objects"
    bl_label = "Find Objects"
    bl_description = ("Group the active run's Gaussians into objects without ground-truth masks: from the "
                      "geometry, or from a folder of 2D masks whose ids need not agree across views")
    masks: bpy.props.StringProperty(name="Mask folder", subtype="DIR_PATH", description="empty: automatic")
    replace: bpy.props.BoolProperty(name="Replace the objects found before", default=True,
                                    description="they are kept: Restore Objects brings them back")

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def segment_args(self, context):
        replace = ["--replace"] if self.replace else []
        return [*(["--from-masks", bpy.path.abspath(self.masks)] if self.masks else ["--auto"]), *replace]


class SPLATFILL_OT_object_from_selection(_SegmentOperator, bpy.types.Operator):
    bl_idname = "splatfill.object_from_selection"
    bl_label = "Object from Selection"
    bl_description = ("The proxy points selected in Edit Mode, or the bounds of the selected mesh that is not "
                      "a proxy, become one more object of the run")
    name: bpy.props.StringProperty(name="Name", default="")

    def segment_args(self, context):
        if context.mode == "EDIT_MESH":
            bpy.ops.object.mode_set(mode="OBJECT")  # selection flags reach the mesh data on leaving Edit Mode
        chosen = selected_gaussians(context.selected_objects or [context.active_object])
        name = ["--name", self.name] if self.name else []
        if len(chosen):
            path = Path(tempfile.mkdtemp(prefix="splatfill-selection-")) / "indices.txt"
            np.savetxt(path, chosen, fmt="%d")
            return ["--indices", str(path), *name]
        frame = next((o for o in run_collection(context).objects if "splatfill_frame" in o), None)
        box = selection_box([o for o in context.selected_objects if "splatfill_group" not in o], frame)
        if box is None:
            raise UserError("select proxy points in Edit Mode, or a mesh (a cube) around the object")
        return ["--box", *map(str, box), *name]


class SPLATFILL_OT_restore_objects(_SegmentOperator, bpy.types.Operator):
    bl_idname = "splatfill.restore_objects"
    bl_label = "Restore Objects"
    bl_description = ("Bring back the objects the last Find Objects or Object from Selection replaced or extended "
                      "(Blender's Undo does not reach the engine's files); again swaps forward")

    def segment_args(self, context):
        return ["--restore"]


def selected_gaussians(objects: list[bpy.types.Object]) -> np.ndarray:
    """Indices of the Gaussians whose proxy points are selected (the `gaussian` point attribute)."""
    chosen = []
    for obj in objects:
        if obj is None or "splatfill_group" not in obj or "gaussian" not in obj.data.attributes:
            continue
        mesh = obj.data
        flags = np.zeros(len(mesh.vertices), bool)
        mesh.vertices.foreach_get("select", flags)
        index = np.zeros(len(mesh.vertices), np.int32)
        mesh.attributes["gaussian"].data.foreach_get("value", index)
        chosen.append(index[flags])
    return np.unique(np.concatenate(chosen)) if chosen else np.zeros(0, np.int64)


def selection_box(objects: list[bpy.types.Object], frame: bpy.types.Object | None) -> list[float] | None:
    """x0 y0 z0 x1 y1 z1 around the selected meshes' bounds, in the engine's world (the run's upright
    `frame` undone)."""
    corners = []
    for obj in objects:
        if obj.type != "MESH":
            continue
        local = np.array([list(c) + [1.0] for c in obj.bound_box])
        corners.append((local @ engine_matrix(obj, frame).T)[:, :3])
    if not corners:
        return None
    points = np.concatenate(corners)
    return [*points.min(0).tolist(), *points.max(0).tolist()]


class SPLATFILL_OT_clean_up(EngineOperator, bpy.types.Operator):
    bl_idname = "splatfill.clean_up"
    bl_label = "Clean Up"
    bl_description = ("Delete stray Gaussians at once (faint, huge, far from the subject, around the cameras, or "
                      "outside a selected mesh's bounds) into a new run that replaces the active one in the view; "
                      "no relighting")
    min_opacity: bpy.props.FloatProperty(name="Min opacity", default=0.05, min=0.0, max=1.0)
    max_size: bpy.props.FloatProperty(name="Max size", default=0.0, min=0.0, description="largest standard "
                                      "deviation kept, scene units (0: any)")
    max_distance: bpy.props.FloatProperty(name="Max distance", default=0.0, min=0.0, description="from the "
                                          "subject (object_1, else where the cameras look), scene units (0: any)")
    crop: bpy.props.BoolProperty(name="Crop to the selected mesh", default=False)
    around_cameras: bpy.props.BoolProperty(name="Around the cameras", default=False, description="also delete "
                                           "those that hold a camera (a flat colour over whole views)")

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def engine_args(self, context, device):
        self._collection = c = run_collection(context)
        run = Path(c["splatfill_run"])
        self._out = run.parent / f"{run.name}-clean-{stamp()}"
        args = ["clean", "--run", str(run), "--out", str(self._out), "--min-opacity", str(self.min_opacity),
                "--max-size", str(self.max_size), "--max-distance", str(self.max_distance)]
        if self.around_cameras:
            args.append("--around-cameras")
        if self.crop:
            frame = next((o for o in c.objects if "splatfill_frame" in o), None)
            box = selection_box([o for o in context.selected_objects if "splatfill_group" not in o], frame)
            if box is None:
                raise UserError("Crop needs a selected mesh (a cube) around what to keep")
            args += ["--crop", *map(str, box)]
        return args

    def finish(self, context, records):
        done = done_record(records, "clean")
        import_run_ply(layout.RunLayout(self._out).point_cloud, self._out.name, splatfill_run=str(self._out))
        self._collection.hide_viewport = True  # the cleaned run takes its place; the original stays on disk
        return f"deleted {done['deleted']} Gaussians, kept {done['kept']}: {self._out}"


CLASSES = (SPLATFILL_OT_import_capture, SPLATFILL_OT_find_objects, SPLATFILL_OT_object_from_selection,
           SPLATFILL_OT_restore_objects, SPLATFILL_OT_clean_up)


register, unregister = bpy.utils.register_classes_factory(CLASSES)
