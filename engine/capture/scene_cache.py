"""Derived copies of a user's scene folder (undistorted, downscaled), made once into a cache and never into
the user's folder. `SPLATFILL_CACHE` moves the cache (default: $XDG_CACHE_HOME/splatfill or
~/.cache/splatfill). A copy is keyed by what it derives from: the source folder's absolute path, its COLMAP
model's and image folder's modification times, and the kind of copy, so an edited capture gets a new one."""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable
from pathlib import Path

from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.base.progress import emit
from engine.formats.colmap_files import find_model_dir
from engine.formats.layout import SceneLayout
from engine.io.colmap_model import MODEL_FILES

CACHE_ENV = "SPLATFILL_CACHE"


def cached_scene(root: Path, kind: str, build: Callable[[Path], None]) -> Path:
    """The cached copy `kind` of scene `root`, made by `build(folder)` into a new folder when missing."""
    cache = _cache_root() / f"{kind}-{_key(root.resolve(), kind)}"
    if SceneLayout(cache).sparse.is_dir():
        return cache
    emit("scene-cache", scene=str(root), kind=kind, cache=str(cache))
    try:
        with atomic_output_dir(cache) as tmp:
            build(tmp)
    except InputError:  # two trainings of one scene at once: the first copy made is the one both read
        if not SceneLayout(cache).sparse.is_dir():
            raise
    return cache


def _cache_root() -> Path:
    if os.environ.get(CACHE_ENV):
        return Path(os.environ[CACHE_ENV])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "splatfill"


def _key(root: Path, kind: str) -> str:
    stamps = [str(root), kind]
    model_dir = find_model_dir(root)
    for stem in MODEL_FILES:
        stamps += [f"{p.name}:{p.stat().st_mtime_ns}:{p.stat().st_size}" for p in sorted(model_dir.glob(f"{stem}.*"))]
    images = SceneLayout(root).images
    if images.is_dir():
        stamps.append(f"images:{images.stat().st_mtime_ns}")
    return hashlib.sha1("|".join(stamps).encode()).hexdigest()[:16]
