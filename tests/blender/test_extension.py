"""The extension: its manifest validates, its zip builds, installs, registers, runs the engine, unregisters."""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import addon_utils
import bpy
import pytest

REPO = Path(__file__).resolve().parents[2]
EXT_TOOL = Path(bpy.utils.system_resource("SCRIPTS")) / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"
MODULE = "bl_ext.user_default.splatfill"


@pytest.fixture(scope="module")
def extension_zip(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("dist")
    proc = subprocess.run([sys.executable, str(EXT_TOOL), "build", "--source-dir", str(REPO), "--output-dir",
                           str(out)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return next(out.glob("splatfill-*.zip"))


def test_manifest_validates():
    proc = subprocess.run([sys.executable, str(EXT_TOOL), "validate", str(REPO)], capture_output=True, text=True)
    assert proc.returncode == 0 and "Success" in proc.stdout, proc.stdout + proc.stderr


def test_zip_carries_the_code_but_no_environments_tests_or_developer_tools(extension_zip: Path):
    names = zipfile.ZipFile(extension_zip).namelist()
    assert "blender_manifest.toml" in names and "engine/capture/scene.py" in names
    assert "operators/check_engine.py" in names
    assert "scripts/make_scene.py" in names and "engine/requirements.txt" in names  # what Set up Engine installs
    assert not [n for n in names if n.startswith((".venv", "tests/", ".git", "benchmarks/", "docs/"))]


def test_extension_installs_registers_runs_the_engine_and_unregisters(extension_zip: Path, monkeypatch):
    monkeypatch.setenv("SPLATFILL_ENGINE_PYTHON", str(REPO / ".venv" / "bin" / "python"))
    result = bpy.ops.extensions.package_install_files(filepath=str(extension_zip), repo="user_default",
                                                      enable_on_install=True)
    assert result == {"FINISHED"}
    assert MODULE in bpy.context.preferences.addons
    assert bpy.context.preferences.addons[MODULE].preferences.device == "cuda"
    assert bpy.ops.splatfill.check_engine() == {"FINISHED"}  # a real engine subprocess answered
    addon_utils.disable(MODULE, default_set=True)
    assert MODULE not in bpy.context.preferences.addons
    assert not hasattr(bpy.types, "SPLATFILL_OT_check_engine")


def test_the_gemini_key_reaches_the_engine_only_through_its_environment(extension_zip: Path, tmp_path: Path,
                                                                         monkeypatch):
    """The key set in the preferences reaches the engine (it says so, by name), and is in none of Blender's
    os.environ, the engine's output stream, its error log, or a saved .blend."""
    secret = "sk-test-0123456789-not-a-real-key"
    monkeypatch.delenv("GEMINI_API_KEY", raising=False)
    monkeypatch.delenv("SPLATFILL_ENGINE_PYTHON", raising=False)
    before = dict(os.environ)
    assert bpy.ops.extensions.package_install_files(filepath=str(extension_zip), repo="user_default",
                                                    enable_on_install=True) == {"FINISHED"}
    try:
        prefs = bpy.context.preferences.addons[MODULE].preferences
        prefs.nanobanana_key = secret
        prefs.engine_python = str(REPO / ".venv" / "bin" / "python")
        assert bpy.ops.splatfill.check_engine() == {"FINISHED"}
        engine_operator = importlib.import_module(f"{MODULE}.operators.engine_operator")
        engine_call = importlib.import_module(f"{MODULE}.addon.engine_call")
        settings = engine_operator.engine_settings()
        job = engine_call.EngineJob(["version"], settings.python, settings.env)
        records = job.result()
        assert next(r for r in records if r.get("event") == "version")["keys"] == ["GEMINI_API_KEY"]
        assert dict(os.environ) == before, "Blender's own environment changed"
        assert secret not in json.dumps(records)
        blend = tmp_path / "scene.blend"
        bpy.ops.wm.save_as_mainfile(filepath=str(blend))
        assert secret.encode() not in blend.read_bytes()
    finally:
        addon_utils.disable(MODULE, default_set=True)


def test_the_installed_extensions_set_up_engine_uses_its_user_folder(extension_zip: Path, monkeypatch):
    """Installed from the zip, with no checkout named anywhere: Set up Engine finds the environment in the
    extension's user folder (linked to the checkout's .venv here, standing for one it made before), checks it,
    and the preferences' Engine Python then names it."""
    monkeypatch.delenv("SPLATFILL_ENGINE_PYTHON", raising=False)
    monkeypatch.delenv("SPLATFILL_WEIGHTS", raising=False)
    assert bpy.ops.extensions.package_install_files(filepath=str(extension_zip), repo="user_default",
                                                    enable_on_install=True) == {"FINISHED"}
    try:
        folder = Path(bpy.utils.extension_path_user(MODULE, path="", create=True))
        env = folder / "engine-env"
        if not env.exists():
            env.symlink_to(REPO / ".venv", target_is_directory=True)
        (folder / "weights").mkdir(exist_ok=True)
        for weight in (REPO / ".weights").iterdir():
            if weight.is_file() and not (folder / "weights" / weight.name).exists():
                (folder / "weights" / weight.name).symlink_to(weight)
        prefs = bpy.context.preferences.addons[MODULE].preferences
        prefs.engine_python = ""
        assert bpy.ops.splatfill.setup_engine() == {"FINISHED"}
        assert prefs.engine_python == str(env / "bin" / "python")
        assert "== check the engine" in (folder / "setup.log").read_text()
    finally:
        addon_utils.disable(MODULE, default_set=True)
