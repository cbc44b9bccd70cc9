"""What every stage may use: the one user-facing error type, progress, atomic output folders, device selection,
weight-file lookup, nearest neighbours, the plug-in registry and the command-line options made from settings
dataclasses. Imports nothing of the engine above it; errors.py imports nothing at all, because Blender-side code
reaches it through engine.formats."""
