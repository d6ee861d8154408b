"""Silencing libraries that write straight to the process's stderr (libpng, OpenCV's back-ends).

Their messages bypass Python, so they cannot be caught; a failure is reported instead as one
clear line of ours. While silenced, nothing else can write to stderr either (a native crash
within the block prints nothing), so it is for calls that write nothing of ours: opening a
camera or a file at start-up, and ``tabletop track`` decoding each frame of a video (FFmpeg's
lines about a damaged frame), a few system calls a frame.
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
