"""What the plug-in registries (completion methods, inpainters) share: how a plug-in says what it needs,
and the user's own plug-in files named by SPLATFILL_PLUGINS."""

from __future__ import annotations

import importlib
import importlib.util
import os
import pkgutil
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Generic, TypeVar

from engine.base.errors import InputError

PLUGIN_PATH_ENV = "SPLATFILL_PLUGINS"  # extra plug-in files or folders, os.pathsep-separated
T = TypeVar("T")


@dataclass(frozen=True)
class Needs:
    """What a plug-in needs beyond the engine's own packages (the README and the Blender menus show it)."""

    weights: tuple[str, ...] = ()  # e.g. "LPIPS backbone (--lpips-backbone)"
    gpu: bool = False  # True: impractical on a CPU
    packages: tuple[str, ...] = ()  # e.g. "pycolmap"
    keys: tuple[str, ...] = ()  # environment variables holding secrets, e.g. "GEMINI_API_KEY"

    def describe(self) -> str:
        parts = [*self.weights, *self.keys, *self.packages] + (["a GPU"] if self.gpu else [])
        return ", ".join(parts) or "nothing more"


def load_plugin_files() -> None:
    """Import the plug-in files (or every .py in the folders) named by SPLATFILL_PLUGINS: a user's own
    methods and inpainters, registered without touching the engine's folders."""
    for entry in filter(None, os.environ.get(PLUGIN_PATH_ENV, "").split(os.pathsep)):
        path = Path(entry)
        files = sorted(path.glob("*.py")) if path.is_dir() else [path]
        for file in files:
            if not file.is_file():
                raise InputError(f"plug-in {file} named in {PLUGIN_PATH_ENV} does not exist; fix the path")
            name = f"splatfill_plugin_{file.stem}"
            if name in sys.modules:
                continue
            spec = importlib.util.spec_from_file_location(name, file)
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module
            spec.loader.exec_module(module)




class Registry(Generic[T]):
    """Plug-in classes by name: every module of the package `package` (one file a plug-in) and the user's files on
    SPLATFILL_PLUGINS are imported the first time the registry is asked, so adding a plug-in is one new file."""

    def __init__(self, kind: str, package: str) -> None:
        self.kind, self.package = kind, package
        self._classes: dict[str, type[T]] = {}

    def add(self, name: str, cls: type[T]) -> type[T]:
        if not name:
            raise TypeError(f"{cls.__name__} declares no name")
        self._classes[name] = cls
        return cls

    def _discover(self) -> None:
        package = importlib.import_module(self.package)
        for module in pkgutil.iter_modules(package.__path__):
            importlib.import_module(f"{self.package}.{module.name}")
        load_plugin_files()

    def classes(self) -> dict[str, type[T]]:
        """Every registered class by name, sorted by name."""
        self._discover()
        return {name: self._classes[name] for name in sorted(self._classes)}

    def names(self) -> list[str]:
        return list(self.classes())

    def get(self, name: str) -> type[T]:
        """The class registered as `name`; an unknown name is one line listing the known ones."""
        found = self.classes()
        if name not in found:
            raise InputError(f"unknown {self.kind} {name!r}; choose from {', '.join(found)}")
        return found[name]
