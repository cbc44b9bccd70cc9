"""splatfill engine: scene I/O, training, removal, hole masks, inpainting, completion, metrics.

Pure numpy/torch; never imports bpy. Blender-side code talks to it only through files on disk
and the JSON-lines progress stream of `python -m engine ...`.
"""

__version__ = "0.1.0"
