"""Shared fixtures: tiny generated scenes, a tiny trained run and its removal, each made once per test run through
the real generator and stages, and shared by every pytest-xdist worker of that run (a file lock; the first
worker to ask makes it)."""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
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
SLOW_FIXTURES = {"scenes_dir", "living_scene", "statue_scene", "any_scene", "tiny_run", "tiny_stages",
                 "extension_zip"}


def pytest_configure(config) -> None:
    if os.environ.get("PYTEST_XDIST_WORKER"):  # workers share the cores: one thread each, not two fighting each
        os.environ["OMP_NUM_THREADS"] = os.environ["MKL_NUM_THREADS"] = "1"
    # scores stay hermetic: the weights `make setup` took from registry packages are found only where a test
    # names them (tests/metrics/test_metrics.py), so a test that expects "n/a" gets it on a set-up machine too
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


def made_once(tmp_path_factory, name: str, make: Callable[[Path], object]) -> Path:
    """`make(folder)` run once per test run, whichever worker asks first; the others wait and read its folder."""
    from filelock import FileLock  # the engine's environment (tests/blender runs without it)

    base = tmp_path_factory.getbasetemp()
    root = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "made-once"
    root.mkdir(exist_ok=True)
    out, done = root / name, root / f"{name}.done"
    with FileLock(str(root / f"{name}.lock")):
        if not done.exists():
            shutil.rmtree(out, ignore_errors=True)
            make(out)
            done.touch()
    return out


@pytest.fixture(scope="session")
def scenes_dir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("scenes")


def tiny_scene(tmp_path_factory, family: str) -> Path:
    return made_once(tmp_path_factory, f"scene-{family}", lambda out: make_scene(out, family))


@pytest.fixture(scope="session")
def living_scene(tmp_path_factory) -> Path:
    return tiny_scene(tmp_path_factory, "livingroom")


@pytest.fixture(scope="session")
def statue_scene(tmp_path_factory) -> Path:
    return tiny_scene(tmp_path_factory, "statue")


@pytest.fixture(scope="session", params=["tabletop", "statue", "livingroom"])
def any_scene(request, tmp_path_factory) -> Path:
    return tiny_scene(tmp_path_factory, request.param)


def _train_tiny(scene: Path, out: Path) -> None:
    from engine.train.config import TrainConfig
    from engine.train.run import train

    # test sizes: 800 steps on the preset's 200-step densification (stretched, it would densify until 600
    # and quadruple the Gaussians every later test renders)
    train(TrainConfig(scene=str(scene), out=str(out), preset="tiny", device="cpu", steps=800,
                      refine_start=50, refine_stop=150))


@pytest.fixture(scope="session")
def tiny_run(living_scene, tmp_path_factory) -> Path:
    """A finished CPU training run (tiny preset) on the tiny livingroom scene, shared by the later stages."""
    return made_once(tmp_path_factory, "run-livingroom", lambda out: _train_tiny(living_scene, out))


def _remove_plush(run: Path, out: Path) -> None:
    from engine.edit.holes import HoleConfig, run_holes
    from engine.edit.removal import RemovalConfig, run_removal

    run_removal(RemovalConfig(run=str(run), object="plush", out=str(out / "removed"), device="cpu"))
    run_holes(HoleConfig(run=str(run), removed=str(out / "removed"), out=str(out / "holes")))


@pytest.fixture(scope="session")
def tiny_stages(tiny_run: Path, tmp_path_factory) -> dict[str, Path]:
    """The tiny run with its target (the plush) removed and its hole masks; `work` is this worker's own folder."""
    done = made_once(tmp_path_factory, "removed-plush", lambda out: _remove_plush(tiny_run, out))
    return {"run": tiny_run, "removed": done / "removed", "holes": done / "holes",
            "work": tmp_path_factory.mktemp("stages-work")}
