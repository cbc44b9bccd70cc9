"""Atomic output folders: work happens in a hidden temporary sibling that is renamed into place.

So an interrupted or failed run never leaves a half-written folder, and existing results and inputs
are never overwritten.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from engine.base.errors import InputError


def check_new_output(final: Path) -> None:
    """Fail early when `final` already holds something."""
    if final.exists() and (not final.is_dir() or any(final.iterdir())):
        raise InputError(f"output {final} already exists and is not empty: choose a new folder or delete it")


@contextmanager
def atomic_output_dir(final: Path, replace: bool = False) -> Iterator[Path]:
    """Yield a temporary folder; on success it becomes `final`, on any error it is removed. With `replace`,
    an existing `final` (an output of ours that the new one extends) is swapped out only once the new one is
    complete."""
    final = Path(final)
    if not replace:
        check_new_output(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = final.parent / f".{final.name}.tmp-{os.getpid()}"
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir()
    try:
        yield tmp
        old = final.parent / f".{final.name}.old-{os.getpid()}"
        if replace and final.exists():
            final.rename(old)
        elif final.is_dir() and not any(final.iterdir()):
            final.rmdir()  # an empty folder given as the output (Windows renames onto nothing at all)
        try:  # a folder another process filled meanwhile stays as it is
            tmp.rename(final)
        except OSError as error:
            raise InputError(f"{final} was written by another process while this one ran: its output is kept, "
                             "this one's dropped; run again with a new folder") from error
        shutil.rmtree(old, ignore_errors=True)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
