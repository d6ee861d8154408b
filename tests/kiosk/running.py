"""A kiosk's installation run in a thread while a test watches it: its loop, and a sink that
keeps what the last frame drew."""

import threading
from contextlib import contextmanager
from typing import Any, Iterator


class Latest:
    """A sink keeping the last frame's characters."""
    name = "latest"

    def __init__(self):
        self.characters = ()

    def consume(self, frame):
        self.characters = frame.characters

    def close(self):
        pass


@contextmanager
def running(inst: Any, seconds: float, run_out: bool = False) -> Iterator[None]:
    """``inst``'s loop run for at most ``seconds`` in a thread while the block runs; after the
    block the loop is stopped (``run_out``: left to run its ``seconds`` out, so its recording
    holds all of them) and the thread joined (30 s at most)."""
    th = threading.Thread(target=inst.loop.run, kwargs={"seconds": seconds})
    th.start()
    try:
        yield
    finally:
        if run_out:
            th.join(30)
        inst.loop.stop.set()
        th.join(30)
