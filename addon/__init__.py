"""Blender-side glue: preferences, running the engine, and conversions between Blender data and the engine's files.

Never imports torch. Modules here that need bpy import it themselves, so that plain helpers such as
engine_call stay usable from scripts run with any Python.
"""

from __future__ import annotations


def register() -> None:
    from . import preferences

    preferences.register()


def unregister() -> None:
    from . import preferences

    preferences.unregister()
