"""Silencing libraries that write straight to the process's stderr (libpng, OpenCV's back-ends).

Their messages bypass Python, so they cannot be caught; a failure is reported instead as one
clear line of ours. Only for short calls at start-up: while silenced, nothing else can write to
stderr either.
"""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Iterator


@contextlib.contextmanager
def quiet_stderr() -> Iterator[None]:
    """File descriptor 2 goes to /dev/null within the block."""
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError):  # no stderr to silence
        yield
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 2)
    try:
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)
