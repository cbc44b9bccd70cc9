"""Set up Engine from the preferences: an environment made offline from a wheel folder (the failing step named),
and one already there checked and then used by the engine operators."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import bpy
import pytest

pytestmark = pytest.mark.slow  # each makes or checks a Python environment
REPO = Path(__file__).resolve().parents[2]


def _probe_wheel(folder: Path) -> None:
    """A minimal pure-Python wheel, splatfill_probe 0.1, with a RECORD pip accepts."""
    import base64
    import hashlib
    import zipfile

    files = {"splatfill_probe/__init__.py": "VALUE = 1\n",
             "splatfill_probe-0.1.dist-info/METADATA": "Metadata-Version: 2.1\nName: splatfill-probe\nVersion: 0.1\n",
             "splatfill_probe-0.1.dist-info/WHEEL": "Wheel-Version: 1.0\nGenerator: test\nRoot-Is-Purelib: true\n"
                                                    "Tag: py3-none-any\n"}
    digest = lambda text: base64.urlsafe_b64encode(hashlib.sha256(text.encode()).digest()).rstrip(b"=").decode()  # noqa: E731
    record = [f"{name},sha256={digest(text)},{len(text.encode())}" for name, text in files.items()]
    files["splatfill_probe-0.1.dist-info/RECORD"] = "\n".join([*record, "splatfill_probe-0.1.dist-info/RECORD,,", ""])
    folder.mkdir(parents=True)
    with zipfile.ZipFile(folder / "splatfill_probe-0.1-py3-none-any.whl", "w") as wheel:
        for name, text in files.items():
            wheel.writestr(name, text)


def _fresh_setup_folder() -> Path:
    import shutil

    from addon.preferences import ENV_FOLDER, WEIGHTS_FOLDER, setup_folder

    folder = setup_folder()
    for name in (ENV_FOLDER, WEIGHTS_FOLDER, "setup.log"):
        path = folder / name
        if path.is_symlink() or path.is_file():
            path.unlink()
        elif path.exists():
            shutil.rmtree(path)
    return folder


def test_set_up_engine_makes_an_environment_offline_and_names_the_step_that_fails(registered, tmp_path: Path):
    """Set up Engine from a local wheel folder only (an offline machine): the venv is made in the user folder and
    the requirements installed from that folder; the requirements here are one small wheel this test builds, so
    the next step (the weights, which runs the engine and so needs its torch) fails, in one line naming the
    step and the log, and the preferences are left alone."""
    from addon.engine_call import EngineError
    from addon.engine_setup import SetupConfig, SetupJob, env_python
    from addon.preferences import ENV_FOLDER, WEIGHTS_FOLDER

    folder = _fresh_setup_folder()
    _probe_wheel(tmp_path / "wheels")
    (tmp_path / "requirements.txt").write_text("splatfill-probe==0.1\n")
    with pytest.raises(RuntimeError, match=r"set-up step 'take the weights' failed \(ModuleNotFoundError.*setup.log"):
        bpy.ops.splatfill.setup_engine(wheels=str(tmp_path / "wheels"), requirements=str(tmp_path / "requirements.txt"))
    python = env_python(folder / ENV_FOLDER)
    probe = subprocess.run([str(python), "-c", "import splatfill_probe; print(splatfill_probe.VALUE)"],
                           capture_output=True, text=True)
    assert probe.stdout.strip() == "1", probe.stderr
    assert "== take the weights" in (folder / "setup.log").read_text()
    job = SetupJob(SetupConfig(env_dir=folder / ENV_FOLDER, weights_dir=folder / WEIGHTS_FOLDER,
                               wheels=str(tmp_path / "wheels")))
    assert [label for label, _ in job.steps] == ["take the weights", "check the engine"]  # the venv is there
    with pytest.raises(EngineError, match=r"set-up step 'take the weights' failed"):
        job.run()


def test_set_up_engine_checks_an_environment_already_there_and_the_engine_then_uses_it(registered, monkeypatch):
    """An environment in the user folder (here the checkout's .venv, linked in) with its weights: Set up Engine
    only takes the weights it lacks (none) and runs `engine version`; engine operators then run that Python
    with those weights."""
    from addon.preferences import ENV_FOLDER, WEIGHTS_FOLDER

    folder = _fresh_setup_folder()
    (folder / ENV_FOLDER).symlink_to(REPO / ".venv", target_is_directory=True)
    (folder / WEIGHTS_FOLDER).mkdir()
    for weight in (REPO / ".weights").iterdir():
        if weight.is_file():
            (folder / WEIGHTS_FOLDER / weight.name).symlink_to(weight)
    monkeypatch.delenv("SPLATFILL_ENGINE_PYTHON", raising=False)
    monkeypatch.delenv("SPLATFILL_WEIGHTS", raising=False)
    assert bpy.ops.splatfill.setup_engine() == {"FINISHED"}
    log = (folder / "setup.log").read_text()
    assert "== check the engine" in log and "== install" not in log and "splatfill engine" in log
    engine_operator = sys.modules["splatfill.operators.engine_operator"]
    settings = engine_operator.engine_settings()
    assert settings.python == str(folder / ENV_FOLDER / "bin" / "python")
    assert settings.env["SPLATFILL_WEIGHTS"] == str(folder / WEIGHTS_FOLDER)
    assert bpy.ops.splatfill.check_engine() == {"FINISHED"}
