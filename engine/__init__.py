"""splatfill engine: scenes in, training, objects, removal, hole masks, inpainting, completion, metrics.

Pure numpy/torch; never imports bpy. Blender-side code talks to it only through files on disk
and the JSON-lines progress stream of `python -m engine ...`. The stages are packages, each importing only
those below it (checked by tests/cli/test_architecture.py; docs/ARCHITECTURE.md draws it):

    cli -> commands -> complete -> inpaint -> edit -> segment -> convert -> train -> pictures -> metrics
        -> render -> capture -> geometry -> io -> formats -> base
"""

__version__ = "0.1.0"
