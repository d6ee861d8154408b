"""Inputs of a replay: recorded frames fed to the loop (:class:`tabletop.loop.Loop`) in place
of live sources, optionally at their recorded pace."""

from __future__ import annotations

import threading
import time
from typing import Callable, Iterator

from tabletop.frames import Frame


class FrameInputs:
    """Inputs from a sequence of recorded frames (replay), optionally paced by their times.

    Each recorded frame keeps its seq and t; its characters are dropped so the engines make them
    again. With ``honour_times`` the next frame is released when its recorded time, relative to the
    first, has elapsed on the loop's clock. Recorded times are not this machine's capture
    times, so no capture-to-render latency is measured.
    """

    live = False

    def __init__(self, frames: Iterator[Frame], honour_times: bool = True,
                 clock: Callable[[], float] = time.monotonic,
                 stop: threading.Event | None = None) -> None:
        self.frames, self.honour_times, self.clock = frames, honour_times, clock
        self.stop = stop or threading.Event()  # ends a wait for the next frame at once
        self._t0: float | None = None
        self._wall0 = 0.0

    def open(self) -> None:
        pass

    def close(self) -> None:
        pass

    def next(self, seq: int, now: float) -> Frame | None:
        frame = next(self.frames, None)
        if frame is None:
            return None
        if self.honour_times:
            if self._t0 is None:
                self._t0, self._wall0 = frame.t, self.clock()
            delay = (frame.t - self._t0) - (self.clock() - self._wall0)
            if delay > 0 and self.stop.wait(delay):
                return None
        return Frame(seq=frame.seq, t=frame.t, pucks=frame.pucks, touches=frame.touches,
                     streams=frame.streams, commands=frame.commands, health=frame.health,
                     focus=frame.focus,   # (a hot reload is played again from its frame)
                     consumed={k: v for k, v in frame.consumed.items() if k == "reload"})
