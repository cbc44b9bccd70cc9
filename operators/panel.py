"""The sidebar panel (3D View > N > splatfill): the pipeline's operators in order, and the active run."""

from __future__ import annotations

import bpy


class SPLATFILL_PT_pipeline(bpy.types.Panel):
    bl_label = "splatfill"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "splatfill"

    def draw(self, context: bpy.types.Context) -> None:
        layout = self.layout
        col = layout.column(align=True)
        col.operator("splatfill.import_capture", icon="IMPORT")
        col.operator("splatfill.import_colmap", icon="CAMERA_DATA")
        col.operator("splatfill.import_splats", icon="IMPORT")
        col.operator("splatfill.train", icon="PLAY")
        col = layout.column(align=True)
        col.operator("splatfill.find_objects", icon="OUTLINER_OB_GROUP_INSTANCE")
        col.operator("splatfill.object_from_selection", icon="RESTRICT_SELECT_OFF")
        col.operator("splatfill.restore_objects", icon="LOOP_BACK")
        col.operator("splatfill.clean_up", icon="BRUSH_DATA")
        col = layout.column(align=True)
        col.operator("splatfill.remove_selected", icon="TRASH")
        col.operator("splatfill.hole_masks", icon="MOD_MASK")
        col.operator("splatfill.inpaint", icon="BRUSH_DATA")
        col.operator("splatfill.complete", icon="CHECKMARK")
        col.operator("splatfill.evaluate", icon="GRAPH")
        col.operator("splatfill.turntable", icon="RENDER_ANIMATION")
        col.operator("splatfill.export", icon="EXPORT")
        col.operator("splatfill.check_engine", icon="CONSOLE")
        obj = context.active_object
        if obj is not None and "splatfill_group" in obj:
            layout.label(text=f"{obj.name}: group {obj['splatfill_group']}, {len(obj.data.vertices):,} Gaussians")
        box = layout.box().column(align=True)  # what Blender's undo does not reach, said where the buttons are
        for line in UNDO_NOTE:
            box.label(text=line)


# Every step writes a new folder in the run and imports it as a new collection; Undo takes the collection back
# but not the folder. Only the objects found live in place (RUN/segments), and Restore Objects swaps them back.
UNDO_NOTE = ("Undo removes what a step imported;", "its folder in the run stays.",
             "Restore Objects undoes Find Objects", "and Object from Selection.")


def register() -> None:
    bpy.utils.register_class(SPLATFILL_PT_pipeline)


def unregister() -> None:
    bpy.utils.unregister_class(SPLATFILL_PT_pipeline)
