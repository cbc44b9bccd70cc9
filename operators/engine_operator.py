"""The pattern every engine operator shares: start the engine as a subprocess, show its progress, let Esc
cancel it, report its error, and hand its output to the operator when it finishes.

In the UI the operator is modal: a 0.2 s timer drains the job's JSON lines into Blender's progress bar and
the status bar, so the UI never blocks. Under `blender -b` timers never fire, so the same operator runs
the engine synchronously. Results are imported in `finish` on the main thread; the operator's UNDO flag
makes the import one undo step.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import bpy

from ..addon.engine_call import EngineError, EngineJob, run_engine
from ..addon.engine_setup import env_python
from ..addon.preferences import ENV_FOLDER, WEIGHTS_FOLDER, preferences, setup_folder


class UserError(Exception):
    """Something the user must fix before the engine can run (nothing selected, no run folder)."""


@dataclass
class EngineSettings:
    """What the preferences say about running the engine: its device, its Python (empty: the default) and
    the variables for its own environment (weight paths and the Gemini key; never Blender's os.environ)."""

    device: str = "auto"
    python: str = ""
    env: dict[str, str] = field(default_factory=dict)


def engine_settings() -> EngineSettings:
    """The preferences' settings; where they name no Python, the environment Set up Engine made (unless
    SPLATFILL_ENGINE_PYTHON names one), with the weights it took."""
    prefs, folder = preferences(), setup_folder()
    made = env_python(folder / ENV_FOLDER)
    default = str(made) if made.is_file() and not os.environ.get("SPLATFILL_ENGINE_PYTHON") else ""
    weights = (folder / WEIGHTS_FOLDER).is_dir() and not os.environ.get("SPLATFILL_WEIGHTS")
    env = {"SPLATFILL_WEIGHTS": str(folder / WEIGHTS_FOLDER)} if weights else {}
    if prefs is None:  # registered without the extension system (scripts, tests): the engine picks
        return EngineSettings(python=default, env=env)
    env.update({key: bpy.path.abspath(value) for key, value in (("LPIPS_BACKBONE", prefs.lpips_backbone),
                                                                ("FID_INCEPTION", prefs.fid_weights),
                                                                ("LAMA_MODEL", prefs.lama_model)) if value})
    if prefs.nanobanana_key:
        env["GEMINI_API_KEY"] = prefs.nanobanana_key
    python = bpy.path.abspath(prefs.engine_python) if prefs.engine_python else default
    return EngineSettings(prefs.device, python, env)


class EngineOperator:
    """Mix-in for bpy.types.Operator subclasses: define engine_args() and finish()."""

    bl_options = {"REGISTER", "UNDO"}
    _job: EngineJob | None = None
    _timer = None

    def engine_args(self, context: bpy.types.Context, device: str) -> list[str]:
        raise NotImplementedError

    def finish(self, context: bpy.types.Context, records: list[dict]) -> str:
        """Import what the engine wrote; returns the line to report."""
        raise NotImplementedError

    def execute(self, context: bpy.types.Context) -> set[str]:
        try:
            settings = engine_settings()
            args = self.engine_args(context, settings.device)
            if bpy.app.background:
                return self._done(context, run_engine(args, python=settings.python, env=settings.env))
            self._job = EngineJob(args, settings.python, settings.env)
        except (UserError, EngineError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        return begin_modal(self, context, 1000, 0.2)

    def modal(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
            context.workspace.status_text_set("splatfill: cancelling (the engine saves its progress)...")
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        for record in job.poll():
            if "step" in record and record.get("total"):
                context.window_manager.progress_update(int(1000 * record["step"] / record["total"]))
                context.workspace.status_text_set(f"splatfill {record['stage']}: {record['step']}/{record['total']}"
                                                  "  (Esc cancels)")
        if not job.finished:
            return {"RUNNING_MODAL"}
        end_modal(self, context)
        try:
            return self._done(context, job.result())
        except EngineError as exc:
            self.report({"ERROR"}, f"splatfill: {exc}")
            return {"CANCELLED"}

    def _done(self, context: bpy.types.Context, records: list[dict]) -> set[str]:
        try:
            self.report({"INFO"}, self.finish(context, records))
        except UserError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        return {"FINISHED"}


def begin_modal(operator: bpy.types.Operator, context: bpy.types.Context, total: int, interval: float) -> set[str]:
    """Start a modal operator's progress bar (0..total) and the timer (every `interval` s) that polls its job."""
    wm = context.window_manager
    wm.progress_begin(0, total)
    operator._timer = wm.event_timer_add(interval, window=context.window)
    wm.modal_handler_add(operator)
    return {"RUNNING_MODAL"}


def end_modal(operator: bpy.types.Operator, context: bpy.types.Context) -> None:
    """Undo begin_modal, and clear the status bar."""
    wm = context.window_manager
    wm.event_timer_remove(operator._timer)
    wm.progress_end()
    context.workspace.status_text_set(None)


def done_record(records: list[dict], stage: str) -> dict:
    """The engine's {"event": "done", "stage": stage, ...} line."""
    for record in reversed(records):
        if record.get("event") == "done" and record.get("stage") == stage:
            return record
    raise UserError(f"the engine finished {stage} without reporting its output")
