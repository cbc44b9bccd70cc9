"""Side-by-side pictures: one row per view, one labelled column per folder of same-named PNGs.

The benchmark's per-scene picture (ground truth, then each method's render of the same test view) is
one of these; any folders of renders with the same file names can be compared the same way.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from engine.base.errors import InputError
from engine.base.output_dir import atomic_output_dir
from engine.io.image_io import read_png, write_png
from engine.pictures.preview import label


def _check(columns: list[tuple[str, Path]], views: list[str]) -> None:
    if not columns or not views:
        raise InputError("compare needs at least one column LABEL=DIR and one view")
    for _, folder in columns:
        if not folder.is_dir():
            raise InputError(f"{folder} is not a folder of renders")


def _row(columns: list[tuple[str, Path]], view: str, with_view: bool) -> np.ndarray:
    """One view across the columns, each labelled; a view missing from a column is black with 'missing'."""
    first = next((read_png(f / view) for _, f in columns if (f / view).is_file()), None)
    if first is None:
        raise InputError(f"view {view} is in none of the columns' folders")
    cells = [label(read_png(f / view), f"{view} {name}" if with_view else name) if (f / view).is_file()
             else label(np.zeros_like(first), f"{name}: missing") for name, f in columns]
    return np.concatenate(cells, axis=1)


def compare_sheet(columns: list[tuple[str, Path]], views: list[str], out: Path) -> Path:
    """Write the sheet (a row per view) to `out`."""
    _check(columns, views)
    write_png(out, np.concatenate([_row(columns, view, True) for view in views], axis=0))
    return out


def compare_frames(columns: list[tuple[str, Path]], views: list[str], out: Path) -> Path:
    """One side-by-side PNG per view into the new folder `out` (a turntable's frames), written atomically."""
    _check(columns, views)
    with atomic_output_dir(out) as tmp:
        for view in views:
            write_png(tmp / view, _row(columns, view, False))
    return out
