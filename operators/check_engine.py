"""Check Engine: runs `python -m engine version` in the configured environment and reports the result."""

from __future__ import annotations

import bpy

from ..addon.engine_call import EngineError, run_engine
from .engine_operator import engine_settings


class SPLATFILL_OT_check_engine(bpy.types.Operator):
    bl_idname = "splatfill.check_engine"
    bl_label = "Check splatfill Engine"
    bl_description = "Start the engine in its own Python and report its version and device"

    def execute(self, context: bpy.types.Context) -> set[str]:
        settings = engine_settings()
        try:
            records = run_engine(["version"], python=settings.python, env=settings.env)
        except EngineError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        info = next((r for r in records if r.get("event") == "version"), {})
        keys = ", ".join(info.get("keys") or []) or "none"
        self.report({"INFO"}, f"splatfill engine {info.get('version')} (torch {info.get('torch')}, "
                              f"CUDA: {info.get('cuda')}; keys set: {keys})")
        return {"FINISHED"}


def register() -> None:
    bpy.utils.register_class(SPLATFILL_OT_check_engine)


def unregister() -> None:
    bpy.utils.unregister_class(SPLATFILL_OT_check_engine)
