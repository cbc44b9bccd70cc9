"""The extension's preferences: where the engine's Python lives and which device it uses."""

from __future__ import annotations

import bpy

from .engine_call import REPO_ROOT

EXTENSION_PACKAGE = __package__.rpartition(".")[0]  # the extension's module, e.g. bl_ext.user_default.splatfill


class SplatfillPreferences(bpy.types.AddonPreferences):
    bl_idname = EXTENSION_PACKAGE

    engine_python: bpy.props.StringProperty(
        name="Engine Python",
        description="Python of the engine environment (made by `make setup`); empty = the repo's .venv",
        subtype="FILE_PATH",
        default="",
    )
    device: bpy.props.EnumProperty(
        name="Device",
        items=[("cuda", "CUDA", "Run the engine on the GPU"), ("cpu", "CPU", "Run the engine on the CPU")],
        default="cuda",
    )

    def draw(self, context: bpy.types.Context) -> None:
        layout = self.layout
        layout.prop(self, "engine_python")
        layout.label(text=f"Default: {REPO_ROOT / '.venv'}")
        layout.prop(self, "device")


def preferences() -> SplatfillPreferences | None:
    addon = bpy.context.preferences.addons.get(EXTENSION_PACKAGE)
    return addon.preferences if addon else None


def register() -> None:
    bpy.utils.register_class(SplatfillPreferences)


def unregister() -> None:
    bpy.utils.unregister_class(SplatfillPreferences)
