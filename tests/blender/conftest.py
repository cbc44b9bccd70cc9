"""Blender-side tests, run with the bpy module (.venv-blender) and an isolated user folder."""

from __future__ import annotations

import importlib.util
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


REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def package():
    """The checkout registered as the package Blender would load (relative imports and all)."""
    spec = importlib.util.spec_from_file_location("splatfill", REPO / "__init__.py",
                                                  submodule_search_locations=[str(REPO)])
    module = importlib.util.module_from_spec(spec)
    sys.modules["splatfill"] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def registered(package):
    package.register()
    yield
    package.unregister()
