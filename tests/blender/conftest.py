"""Blender-side tests, run with the bpy module (.venv-blender) and an isolated user folder."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="splatfill-blender-user-"))

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repo: addon/ and scripts/ import as packages
import bpy  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def factory_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield
