"""Check Engine: runs `python -m engine version` in the configured environment and reports the result."""

from __future__ import annotations

import os

import bpy

from ..addon.engine_call import EngineError, run_engine
from ..addon.preferences import preferences


class SPLATFILL_OT_check_engine(bpy.types.Operator):
    bl_idname = "splatfill.check_engine"
    bl_label = "Check splatfill Engine"
    bl_description = "Start the engine in its own Python and report its version and device"

    def execute(self, context: bpy.types.Context) -> set[str]:
        prefs = preferences()
        if prefs is not None and prefs.engine_python:
            os.environ["SPLATFILL_ENGINE_PYTHON"] = bpy.path.abspath(prefs.engine_python)
        try:
            records = run_engine(["version"])
        except EngineError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        info = next((r for r in records if r.get("event") == "version"), {})
        self.report({"INFO"}, f"splatfill engine {info.get('version')} (torch {info.get('torch')}, "
                              f"CUDA: {info.get('cuda')})")
        return {"FINISHED"}


def register() -> None:
    bpy.utils.register_class(SPLATFILL_OT_check_engine)


def unregister() -> None:
    bpy.utils.unregister_class(SPLATFILL_OT_check_engine)
