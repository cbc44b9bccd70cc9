"""Blender-side tests, run with the bpy module (.venv-blender) and an isolated user folder."""

from __future__ import annotations

import os
import tempfile

os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="splatfill-blender-user-"))

import bpy  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def factory_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield
