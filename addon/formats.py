"""The engine's torch-free formats and conventions (engine/formats: splat .ply layout, cameras, the scene
and run folder layout), as Blender-side code reaches them. Blender loads the extension as a package whose
engine/ ships beside addon/, so the import is relative there; scripts and tests import addon/ as a
top-level package from a checkout, where engine/ is top-level too."""

from __future__ import annotations

try:
    from ..engine.base.errors import InputError
    from ..engine.formats import cameras, checks, colmap_files, layout, splat_files, splat_ply
except ImportError:  # addon/ is itself top-level: nothing above it to be relative to
    from engine.base.errors import InputError
    from engine.formats import cameras, checks, colmap_files, layout, splat_files, splat_ply

__all__ = ["InputError", "cameras", "checks", "colmap_files", "layout", "splat_files", "splat_ply"]
