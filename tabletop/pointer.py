"""Fingers made with the mouse in the projector view, for testing touch engines at a desk.

The view writes (table metres); with an engine that takes mouse touches the loop adds them to
every frame's touches (:func:`with_mouse_fingers`, so a recording keeps them). One button held
is one finger that follows the pointer; Shift + click pins a finger where it is (it stays down after
the button is released, as a second hand holding a part); Shift + click on a pinned finger lifts
it. Thread-safe; ids start at :data:`FIRST_ID`, far above the ids a touch source gives in its
first days (a TUIO tracker counts its session ids up for as long as it runs, so the view knows
the mouse's fingers by the ids :meth:`PointerFingers.touches` holds, not by a range).
"""

from __future__ import annotations

import dataclasses
import math
import threading

from tabletop.frames import Frame, Touch

FIRST_ID = 90_000
#: A Shift + click within this many metres of a pinned finger lifts it.
PICK_M = 0.02


class PointerFingers:
    """The mouse's fingers on the table."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._pinned: dict[int, tuple[float, float]] = {}
        self._held: tuple[float, float] | None = None
        self._next = FIRST_ID + 1

    def press(self, x: float, y: float, pin: bool = False) -> None:
        """Button down at table (x, y) metres; ``pin`` (Shift) pins or lifts a pinned finger."""
        with self._lock:
            if pin:
                near = [i for i, (px, py) in self._pinned.items()
                        if math.hypot(px - x, py - y) <= PICK_M]
                if near:
                    del self._pinned[near[0]]
                else:
                    self._pinned[self._next] = (x, y)
                    self._next += 1
            else:
                self._held = (x, y)

    def move(self, x: float, y: float) -> None:
        with self._lock:
            if self._held is not None:
                self._held = (x, y)

    def release(self) -> None:
        with self._lock:
            self._held = None

    def touches(self) -> tuple[Touch, ...]:
        """The fingers down now."""
        with self._lock:
            out = [Touch(i, x, y) for i, (x, y) in self._pinned.items()]
            if self._held is not None:
                out.append(Touch(FIRST_ID, *self._held))
        return tuple(out)


#: The one pointer of this process (the view writes it).
POINTER = PointerFingers()


def with_mouse_fingers(frame: Frame) -> Frame:
    """Loop filter (with an engine taking ``mouse: true``): the mouse's fingers join the frame's
    touches, so every engine sees them as a touch source's, and a recording keeps them (a
    session posed with the mouse replays as it ran)."""
    fingers = POINTER.touches()
    return dataclasses.replace(frame, touches=frame.touches + fingers) if fingers else frame
