"""Sequential training (paper section 3.1): record the main first, then the reactor against
its playback.

With one hand (a mouse, or one puck at a time) the designer first demonstrates an example main
path; the system then replays it, and the designer demonstrates the reaction while watching
it. The two takes make one demonstration: the reactor's samples, with the main's pose
interpolated at their times (angles through their unwrapped signal).

Take arrays: main (n, 4) ``t, x, y, dir`` and reactor (m, 4) ``t, x, y, dir``; the reactor's
times are on the main take's time base (the playback replays the main take's own times).
Seconds, table metres, radians.
"""

from __future__ import annotations

import numpy as np

from tabletop.frames import InputError, wrap_angle, wrap_angles


class TakeError(InputError):
    """Two takes that cannot make a demonstration; the message says why."""


def _check(take: np.ndarray, what: str) -> np.ndarray:
    a = np.asarray(take, dtype=float)
    if a.ndim != 2 or a.shape[1] != 4 or a.shape[0] < 2:
        raise TakeError(f"{what} take must have at least 2 rows of t, x, y, dir; got shape "
                        f"{a.shape}")
    if not np.isfinite(a).all():
        raise TakeError(f"{what} take holds values that are not finite numbers")
    if (np.diff(a[:, 0]) <= 0).any():
        raise TakeError(f"{what} take: times must strictly increase")
    return a


def pair_takes(main: np.ndarray, react: np.ndarray) -> np.ndarray:
    """One demonstration (k, 7) ``t, main_x, main_y, main_dir, react_x, react_y, react_dir``
    from a main take and a reactor take recorded against its playback: the reactor samples
    within the main take's time span, times from 0. Raises TakeError if they do not overlap."""
    m, r = _check(main, "main"), _check(react, "reactor")
    inside = (r[:, 0] >= m[0, 0]) & (r[:, 0] <= m[-1, 0])
    r = r[inside]
    if r.shape[0] < 2:
        raise TakeError(f"the reactor take ({react[0][0]:g}..{react[-1][0]:g} s) does not overlap "
                        f"the main take's playback ({m[0, 0]:g}..{m[-1, 0]:g} s)")
    t = r[:, 0]
    out = np.empty((t.size, 7))
    out[:, 0] = t - t[0]
    out[:, 1] = np.interp(t, m[:, 0], m[:, 1])
    out[:, 2] = np.interp(t, m[:, 0], m[:, 2])
    out[:, 3] = wrap_angles(np.interp(t, m[:, 0], np.unwrap(m[:, 3])))
    out[:, 4:6] = r[:, 1:3]
    out[:, 6] = wrap_angles(r[:, 3])
    return out


class Playback:
    """The main take replayed from a start time: :meth:`at` gives the main pose ``t`` seconds
    of wall time later (linear interpolation), :meth:`take_time` the playback's own time for
    stamping the reactor's samples, and :attr:`duration` when it ends."""

    def __init__(self, main: np.ndarray, start: float) -> None:
        self.main = _check(main, "main")
        self.start = float(start)
        self._unwrapped = np.unwrap(self.main[:, 3])
        self.duration = float(self.main[-1, 0] - self.main[0, 0])

    def take_time(self, now: float) -> float:
        """Time on the main take's base at wall time ``now``."""
        return float(self.main[0, 0]) + (now - self.start)

    def finished(self, now: float) -> bool:
        """True once the whole take has been played."""
        return now - self.start >= self.duration

    def at(self, now: float) -> tuple[float, float, float]:
        """Main pose (x, y, dir) at wall time ``now`` (held at the ends)."""
        tt = self.take_time(now)
        m = self.main
        return (float(np.interp(tt, m[:, 0], m[:, 1])), float(np.interp(tt, m[:, 0], m[:, 2])),
                wrap_angle(float(np.interp(tt, m[:, 0], self._unwrapped))))


class SequentialSession:
    """The designer's two takes at the table, one hand at a time.

    Phases: ``idle`` -> (record) ``main``: the main puck's poses are the main take ->
    (record) ``ready``: the take waits -> (record) ``react``: the main take plays back (drawn
    as a ghost) while the reactor puck's poses are recorded on its time base -> (record, or
    the playback ends) ``done``: :meth:`demonstration` pairs the takes.
    """

    def __init__(self) -> None:
        self.phase = "idle"
        self.main: list[tuple[float, float, float, float]] = []
        self.react: list[tuple[float, float, float, float]] = []
        self.playback: Playback | None = None

    def toggle(self, now: float) -> str:
        """The designer's record key at wall time ``now``; returns the new phase."""
        if self.phase in ("idle", "done"):
            self.phase, self.main, self.react, self.playback = "main", [], [], None
        elif self.phase == "main":
            self.phase = "ready" if len(self.main) >= 2 else "idle"
        elif self.phase == "ready":
            self.playback = Playback(np.array(self.main), now)
            self.phase = "react"
        else:
            self.phase = "done"
        return self.phase

    def record(self, now: float, main: tuple[float, float, float] | None,
               react: tuple[float, float, float] | None) -> tuple[float, float, float] | None:
        """One frame's poses (x, y, dir; None when a puck is absent). Returns the played-back
        main pose during the ``react`` phase (else None)."""
        if self.phase == "main" and main is not None and (not self.main or now > self.main[-1][0]):
            self.main.append((now, *main))
        if self.phase != "react" or self.playback is None:
            return None
        if self.playback.finished(now):
            self.phase = "done"
        tt = self.playback.take_time(now)
        if react is not None and (not self.react or tt > self.react[-1][0]):
            self.react.append((tt, *react))
        return self.playback.at(now)

    def seconds(self) -> float:
        """Length of the take being recorded (s)."""
        take = self.main if self.phase in ("main", "ready") else self.react
        return take[-1][0] - take[0][0] if len(take) > 1 else 0.0

    def demonstration(self) -> np.ndarray:
        """The paired demonstration (k, 7); raises TakeError if the takes do not make one."""
        if len(self.main) < 2 or len(self.react) < 2:
            raise TakeError("both takes need at least two samples")
        return pair_takes(np.array(self.main), np.array(self.react))
