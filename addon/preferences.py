"""The extension's preferences: the engine's Python, its device, where model weights are, the Nano Banana key.

The key is an add-on preference (saved in Blender's userpref.blend, never in a scene's .blend) or the
GEMINI_API_KEY environment variable; it reaches the engine only through its environment, never its
arguments (which a log or the process list would show)."""

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
        layout.prop(self, "engine_python")
        layout.label(text=f"Default: {REPO_ROOT / '.venv'}")
        layout.prop(self, "device")
        for name in ("lpips_backbone", "fid_weights", "lama_model", "nanobanana_key"):
            layout.prop(self, name)


def preferences() -> SplatfillPreferences | None:
    addon = bpy.context.preferences.addons.get(EXTENSION_PACKAGE)
    return addon.preferences if addon else None


def register() -> None:
    bpy.utils.register_class(SplatfillPreferences)


def unregister() -> None:
    bpy.utils.unregister_class(SplatfillPreferences)
