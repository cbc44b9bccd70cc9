"""The extension's preferences: the engine's Python, its device, where model weights are, the Nano Banana key.

The key is an add-on preference (saved in Blender's userpref.blend, never in a scene's .blend) or the
GEMINI_API_KEY environment variable; it reaches the engine only through its environment, never its
arguments (which a log or the process list would show)."""

from __future__ import annotations

from pathlib import Path

import bpy

from .engine_call import REPO_ROOT
from .engine_setup import env_python

EXTENSION_PACKAGE = __package__.rpartition(".")[0]  # the extension's module, e.g. bl_ext.user_default.splatfill


class SplatfillPreferences(bpy.types.AddonPreferences):
    bl_idname = EXTENSION_PACKAGE

    engine_python: bpy.props.StringProperty(
        name="Engine Python",
        description="Python of the engine environment; empty = the one Set up Engine made, else a checkout's .venv",
        subtype="FILE_PATH",
        default="",
    )
    device: bpy.props.EnumProperty(
        name="Device",
        items=[("cuda", "CUDA", "Run the engine on the GPU"), ("cpu", "CPU", "Run the engine on the CPU")],
        default="cuda",
    )

    lpips_backbone: bpy.props.StringProperty(name="LPIPS backbone", subtype="FILE_PATH", default="",
                                             description="alexnet-owt-7be5be79.pth (else LPIPS_BACKBONE or n/a)")
    fid_weights: bpy.props.StringProperty(name="FID Inception", subtype="FILE_PATH", default="",
                                          description="pt_inception-2015-12-05-6726825d.pth (else FID_INCEPTION)")
    lama_model: bpy.props.StringProperty(name="LaMa model", subtype="FILE_PATH", default="",
                                         description="big-lama TorchScript file (else LAMA_MODEL)")
    nanobanana_key: bpy.props.StringProperty(name="Nano Banana key", subtype="PASSWORD", default="",
                                             description="Gemini API key; empty: GEMINI_API_KEY from the environment")

    def draw(self, context: bpy.types.Context) -> None:
        layout = self.layout
        made = env_python(setup_folder() / ENV_FOLDER)
        row = layout.row()
        row.operator("splatfill.setup_engine", icon="CONSOLE")
        row.operator("splatfill.check_engine", icon="CHECKMARK")
        layout.label(text=f"Set-up environment: {made}" + ("" if made.is_file() else " (not made yet)"))
        layout.prop(self, "engine_python")
        layout.label(text=f"Default: the set-up environment, else {REPO_ROOT / '.venv'}")
        layout.prop(self, "device")
        for name in ("lpips_backbone", "fid_weights", "lama_model", "nanobanana_key"):
            layout.prop(self, name)


ENV_FOLDER, WEIGHTS_FOLDER = "engine-env", "weights"  # in setup_folder()


def setup_folder() -> Path:
    """The extension's user folder (kept when the extension updates), where Set up Engine makes the engine's
    environment and puts its weights; registered outside the extension system (a checkout, tests), a
    splatfill folder among the user's scripts."""
    try:
        return Path(bpy.utils.extension_path_user(EXTENSION_PACKAGE, path="", create=True))
    except ValueError:
        return Path(bpy.utils.user_resource("SCRIPTS", path="splatfill", create=True))


def preferences() -> SplatfillPreferences | None:
    addon = bpy.context.preferences.addons.get(EXTENSION_PACKAGE)
    return addon.preferences if addon else None


def register() -> None:
    bpy.utils.register_class(SplatfillPreferences)


def unregister() -> None:
    bpy.utils.unregister_class(SplatfillPreferences)
