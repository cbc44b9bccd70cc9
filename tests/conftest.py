"""Shared fixtures: tiny generated scenes, made once per test session through the real generator."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent

# tests/blender runs in Blender's Python (.venv-blender); the rest in the engine's (.venv). bpy is only
# looked for here, not imported: tests/blender/conftest.py must set up Blender's user folder first.
collect_ignore = [] if importlib.util.find_spec("bpy") else ["blender"]
TINY = ["--views", "8", "--res", "96", "--samples", "4", "--seed", "3", "--points", "3000"]


# Two marks (README, developer section): `slow` is end to end (a generated scene, a training run, Blender
# rendering, an installed extension), `fast` is everything else, on tiny inputs made in the test.
# A test is slow when it asks for a scene, run or built-extension fixture, or says so with @pytest.mark.slow.
SLOW_FIXTURES = {"scenes_dir", "living_scene", "any_scene", "tiny_run", "extension_zip"}


def pytest_configure(config) -> None:
    # scores stay hermetic: the weights `make setup` took from registry packages are found only where a test
    # names them (tests/test_metrics.py), so a test that expects "n/a" gets it on a set-up machine too
    os.environ["SPLATFILL_WEIGHTS"] = str(Path(config.rootpath) / ".pytest_cache" / "no-weights")
    config.addinivalue_line("markers", "slow: end to end: generated scenes, training runs, Blender rendering")
    config.addinivalue_line("markers", "fast: unit tests on tiny inputs (the whole set runs in under 2 minutes)")


def pytest_collection_modifyitems(config, items) -> None:
    for item in items:
        if "slow" in item.keywords or SLOW_FIXTURES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.slow)
        else:
            item.add_marker(pytest.mark.fast)


def setup_weight(name: str) -> Path:
    """A file `make setup` put in .weights/: the tests that use one name it, since SPLATFILL_WEIGHTS points the
    others at an empty folder."""
    path = REPO / ".weights" / name
    assert path.is_file(), f"{path} missing: run `make setup`"
    return path


def blender_command(script: str, args: list[str]) -> list[str]:
    """Run a script the way the README does: through $BLENDER if set, else the bpy environment."""
    blender = os.environ.get("BLENDER")
    if blender:
        return [blender, "-b", "--factory-startup", "-P", str(REPO / script), "--", *args]
    python = REPO / ".venv-blender" / "bin" / "python"
    if not python.is_file():
        pytest.fail(f"{python} missing: run `make setup` (or set BLENDER=/path/to/blender)")
    return [str(python), str(REPO / script), *args]


def make_scene(out: Path, family: str, extra: list[str] = TINY, env: dict | None = None,
               check: bool = True) -> subprocess.CompletedProcess:
    env = {**os.environ, "SPLATFILL_ENGINE_PYTHON": sys.executable, **(env or {})}
    extra = ["--extra-test", "0", *extra]  # tiny CPU scenes: no set metrics, no extra views to render
    proc = subprocess.run(blender_command("scripts/make_scene.py", ["--family", family, "--out", str(out), *extra]),
                          capture_output=True, text=True, env=env, cwd=REPO)
    if check and proc.returncode != 0:
        pytest.fail(f"make_scene failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    return proc


@pytest.fixture(scope="session")
def scenes_dir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("scenes")


@pytest.fixture(scope="session")
def living_scene(scenes_dir) -> Path:
    out = scenes_dir / "livingroom"
    make_scene(out, "livingroom")
    return out


@pytest.fixture(scope="session")
def statue_scene(scenes_dir) -> Path:
    out = scenes_dir / "statue"
    if not out.exists():
        make_scene(out, "statue")
    return out


@pytest.fixture(scope="session", params=["tabletop", "statue", "livingroom"])
def any_scene(request, scenes_dir, living_scene, statue_scene) -> Path:
    if request.param == "livingroom":
        return living_scene
    if request.param == "statue":
        return statue_scene
    out = scenes_dir / request.param
    if not out.exists():
        make_scene(out, request.param)
    return out


@pytest.fixture(scope="session")
def tiny_run(living_scene, tmp_path_factory) -> Path:
    """A finished CPU training run (tiny preset) on the tiny livingroom scene, shared by the later stages."""
    from engine.train.config import TrainConfig
    from engine.train.run import train

    out = tmp_path_factory.mktemp("runs") / "living"
    # test sizes: 800 steps on the preset's 200-step densification (stretched, it would densify until 600
    # and quadruple the Gaussians every later test renders)
    train(TrainConfig(scene=str(living_scene), out=str(out), preset="tiny", device="cpu", steps=800,
                      refine_start=50, refine_stop=150))
    return out
