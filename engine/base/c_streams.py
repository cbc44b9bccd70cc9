"""Keeping C libraries' chatter off the JSON-lines stream and out of the one-line errors.

libpng, OpenCV and OpenImageIO print warnings straight to file descriptors 1 and 2 (a corrupt EXR printed
four lines on stdout, which the add-on parses as JSON lines). Around a decode, both descriptors point at a
temporary file; what the library said comes back to the caller, to put in its error or drop. The descriptors are
the process's, so one capture at a time: two threads' captures interleaved would restore fd 1 to the other's temp
file, and every later line of the process would vanish into it (views are inpainted in threads).
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
import threading
from collections.abc import Iterator

_ONE_AT_A_TIME = threading.RLock()


@contextlib.contextmanager
def captured_c_output() -> Iterator[list[str]]:
    """Within the block, writes to fds 1 and 2 land in a temp file; afterwards the list holds its lines."""
    with _ONE_AT_A_TIME, _captured() as lines:
        yield lines


@contextlib.contextmanager
def _captured() -> Iterator[list[str]]:
    lines: list[str] = []
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, ValueError, OSError):
            stream.flush()
    with tempfile.TemporaryFile() as sink:
        saved = [os.dup(1), os.dup(2)]
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield lines
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
            sink.seek(0)
            lines.extend(sink.read().decode("utf-8", "replace").splitlines())
