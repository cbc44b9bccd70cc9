"""The files the engine and Blender share, numpy only: the 3DGS .ply layout and reader/writer with its SH
constants (splat_ply), cameras and their conventions, cameras.json and the Blender conversion (cameras),
and where every file of a scene or run folder lives (layout).

Blender's Python imports this package inside the installed extension, where `engine` is not a top-level
package, so its modules import each other and engine.base.errors relatively, and nothing else of the
engine; torch, OpenCV, OpenImageIO and plyfile never (tests/cli/test_architecture.py).
"""
