"""Procedural Blender scenes with exact ground truth (runs inside Blender's Python)."""
