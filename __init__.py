"""splatfill as a Blender extension: registers what addon/ (data and preferences) and operators/ define.

Blender loads this package as bl_ext.<repo>.splatfill; the engine (engine/) never loads into Blender,
it runs in its own Python environment as a subprocess.
"""

if __package__:  # as Blender loads it; pytest imports this file alone when the checkout's folder name is
    from . import addon, operators  # not a Python identifier (a clone in "ci-clone/"), and needs none of it


def register() -> None:
    addon.register()
    operators.register()


def unregister() -> None:
    operators.unregister()
    addon.unregister()
