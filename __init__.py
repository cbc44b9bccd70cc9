"""splatfill as a Blender extension: registers what addon/ (data and preferences) and operators/ define.

Blender loads this package as bl_ext.<repo>.splatfill; the engine (engine/) never loads into Blender,
it runs in its own Python environment as a subprocess.
"""

from . import addon, operators


def register() -> None:
    addon.register()
    operators.register()


def unregister() -> None:
    operators.unregister()
    addon.unregister()
