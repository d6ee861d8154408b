"""A scripted visitor: seeded, human-like puck motion for the default installation and the tests.

Each puck walks from waypoint to waypoint on gently curved paths (quadratic Bezier curves) with a
minimum-jerk speed profile, turns toward where it is going, pauses now and then and looks around.
The motion is a pure function of time and seed: ``poses(t)`` gives the same answer for the same t
whatever was asked before, so a test can sample any time in any order.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from tabletop.frames import wrap_angle


def min_jerk(tau: float) -> float:
    """Minimum-jerk position profile s(tau) for tau in [0, 1] (0 -> 0, 1 -> 1, zero end speeds)."""
    tau = min(max(tau, 0.0), 1.0)
    return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau))


def smoothstep(tau: float) -> float:
    tau = min(max(tau, 0.0), 1.0)
    return tau * tau * (3.0 - 2.0 * tau)


HISTORY_S = 600.0   # how far back a script remembers, seconds (a kiosk runs it for weeks)
_FORGET_AT = 64     # stale entries dropped at once (dropping from a list's front is O(n))


def forget(entries: list, starts: list[float], t: float) -> bool:
    """Drop the entries (and their start times, s) that ended over :data:`HISTORY_S` before
    ``t`` (s), once there are enough of them; True when some were dropped."""
    stale = bisect.bisect_right(starts, t - HISTORY_S) - 2   # keep the one holding t - HISTORY_S
    if stale < _FORGET_AT:
        return False
    del entries[:stale]
    del starts[:stale]
    return True


@dataclass(frozen=True)
class Segment:
    """One stretch of a puck's script: a move along a Bezier curve, or a pause (p0 == p2).

    Times in seconds, points in metres, angles in radians.
    """

    t0: float
    t1: float
    p0: tuple[float, float]
    p1: tuple[float, float]  # Bezier control point
    p2: tuple[float, float]
    a0: float  # heading at the start
    a1: float  # heading at the end of a pause (moves: the heading follows the path)
    moving: bool

    def pose(self, t: float) -> tuple[float, float, float]:
        """(x m, y m, heading rad) at ``t`` (s) within this segment."""
        tau = (t - self.t0) / max(self.t1 - self.t0, 1e-9)
        if not self.moving:
            a = self.a0 + wrap_angle(self.a1 - self.a0) * smoothstep(tau)
            return self.p0[0], self.p0[1], wrap_angle(a)
        s = min_jerk(tau)
        x, y = self._bezier(s)
        # Heading: the path's tangent, with the turn from the previous heading (a fixed offset
        # against the start tangent) faded out over the first quarter of the move.
        tangent = math.atan2(*reversed(self._tangent(s)))
        offset = wrap_angle(self.a0 - math.atan2(*reversed(self._tangent(0.0))))
        # A hand turns a puck at up to about 3 rad/s: big turns take longer than a quarter.
        fade = min(1.0, max(0.25, 0.5 * abs(offset) / (self.t1 - self.t0)))
        return x, y, wrap_angle(tangent + offset * (1.0 - smoothstep(tau / fade)))

    def _bezier(self, s: float) -> tuple[float, float]:
        u = 1.0 - s
        x = u * u * self.p0[0] + 2 * u * s * self.p1[0] + s * s * self.p2[0]
        y = u * u * self.p0[1] + 2 * u * s * self.p1[1] + s * s * self.p2[1]
        return x, y

    def _tangent(self, s: float) -> tuple[float, float]:
        dx = 2 * (1 - s) * (self.p1[0] - self.p0[0]) + 2 * s * (self.p2[0] - self.p1[0])
        dy = 2 * (1 - s) * (self.p1[1] - self.p0[1]) + 2 * s * (self.p2[1] - self.p1[1])
        return dx, dy


class PuckScript:
    """The script of one puck, generated lazily segment by segment from its own seeded RNG."""

    def __init__(self, table: tuple[float, float], seed: int, margin: float = 0.08,
                 speed: tuple[float, float] = (0.08, 0.35), pause: tuple[float, float] = (0.4, 2.0),
                 pause_chance: float = 0.45) -> None:
        self.w, self.h = table
        self.margin = min(margin, 0.25 * min(self.w, self.h))
        self.speed, self.pause, self.pause_chance = speed, pause, pause_chance
        self.rng = np.random.default_rng(seed)
        start = self._waypoint()
        a = float(self.rng.uniform(-math.pi, math.pi))
        self.segments: list[Segment] = [Segment(0.0, 0.5, start, start, start, a, a, False)]
        self.starts: list[float] = [0.0]

    def _waypoint(self) -> tuple[float, float]:
        m = self.margin
        return (float(self.rng.uniform(m, self.w - m)), float(self.rng.uniform(m, self.h - m)))

    def _extend(self) -> None:
        last = self.segments[-1]
        p0 = last.p2
        a0 = last.pose(last.t1)[2]
        if last.moving and self.rng.random() < self.pause_chance:
            d = float(self.rng.uniform(*self.pause))
            look = wrap_angle(a0 + float(self.rng.uniform(-1.6, 1.6)))
            seg = Segment(last.t1, last.t1 + d, p0, p0, p0, a0, look, False)
        else:
            p2 = self._waypoint()
            while math.dist(p0, p2) < 0.1 * min(self.w, self.h):
                p2 = self._waypoint()
            mid = ((p0[0] + p2[0]) / 2, (p0[1] + p2[1]) / 2)
            dist = math.dist(p0, p2)
            nx, ny = -(p2[1] - p0[1]) / dist, (p2[0] - p0[0]) / dist
            bend = float(self.rng.uniform(-0.35, 0.35)) * dist
            p1 = (min(max(mid[0] + nx * bend, 0.0), self.w),
                  min(max(mid[1] + ny * bend, 0.0), self.h))
            v = float(self.rng.uniform(*self.speed))
            # Min-jerk peaks at 1.875x its mean speed; the mean is v.
            d = max(dist / v, 0.4)
            seg = Segment(last.t1, last.t1 + d, p0, p1, p2, a0, a0, True)
        self.segments.append(seg)
        self.starts.append(seg.t0)

    def pose(self, t: float) -> tuple[float, float, float]:
        """(x m, y m, angle rad) at time ``t`` seconds (t < 0 is the start pose); times more
        than :data:`HISTORY_S` before the latest asked for get the oldest pose remembered."""
        while self.segments[-1].t1 < t:
            self._extend()
        forget(self.segments, self.starts, t)
        i = max(bisect.bisect_right(self.starts, t) - 1, 0)
        return self.segments[i].pose(max(t, 0.0))


class ScriptedVisitor:
    """A visitor moving pucks ``puck_ids`` about a table of ``table`` = (width, height) metres."""

    def __init__(self, table: tuple[float, float], puck_ids: Sequence[int] = (1, 2),
                 seed: int = 0, **script_options: float) -> None:
        self.table = (float(table[0]), float(table[1]))
        self.puck_ids = tuple(int(i) for i in puck_ids)
        self.scripts = {pid: PuckScript(self.table, seed * 1009 + k * 7919 + 1, **script_options)
                        for k, pid in enumerate(self.puck_ids)}

    def poses(self, t: float) -> list[tuple[int, float, float, float]]:
        """[(id, x m, y m, angle rad), ...] for every puck at time ``t`` seconds."""
        return [(pid, *self.scripts[pid].pose(t)) for pid in self.puck_ids]


class GesturePerformer:
    """A performer drawing recorded gestures with one puck, for action-following demos and tests.

    ``gestures``: arrays of rows (t s, dx m, dy m), paths relative to where the gesture starts.
    From ``home`` the puck rests, draws a gesture chosen by the seeded RNG at a speed factor drawn
    from ``speed`` (1 = as recorded), rests again, and slides back home when it ended elsewhere.
    The puck keeps its heading ``angle``. A pure function of time, like :class:`ScriptedVisitor`.
    """

    def __init__(self, gestures: Sequence[np.ndarray], home: tuple[float, float], seed: int = 0,
                 speed: tuple[float, float] = (0.6, 1.6), rest: tuple[float, float] = (1.2, 2.0),
                 angle: float = 0.0) -> None:
        if not gestures:
            raise ValueError("a gesture performer needs at least one gesture")
        self.gestures = [np.asarray(g, dtype=float) for g in gestures]
        self.home = (float(home[0]), float(home[1]))
        self.speed, self.rest, self.angle = speed, rest, angle
        self.rng = np.random.default_rng(seed)
        # Each entry: (t0, t1, kind, data); kind "rest" (data: point), "gesture" (data: start,
        # index, speed) or "return" (data: from point).
        self.plan: list[tuple[float, float, str, tuple]] = [(0.0, 1.5, "rest", (self.home,))]
        self.starts = [0.0]
        self.performed: list[tuple[float, float, int, float]] = []  # (t0, t1, gesture, speed)

    def _end_point(self, entry: tuple[float, float, str, tuple]) -> tuple[float, float]:
        kind, data = entry[2], entry[3]
        if kind == "rest":
            return data[0]
        if kind == "return":
            return self.home
        start, index, _ = data
        g = self.gestures[index]
        return start[0] + g[-1, 1], start[1] + g[-1, 2]

    def _extend(self) -> None:
        last = self.plan[-1]
        t0 = last[1]
        here = self._end_point(last)
        if last[2] == "rest" and math.dist(here, self.home) > 0.02:
            d = max(math.dist(here, self.home) / 0.15, 0.5)
            entry = (t0, t0 + d, "return", (here,))
        elif last[2] == "rest":
            index = int(self.rng.integers(len(self.gestures)))
            s = float(self.rng.uniform(*self.speed))
            g = self.gestures[index]
            entry = (t0, t0 + (g[-1, 0] - g[0, 0]) / s, "gesture", (here, index, s))
            self.performed.append((entry[0], entry[1], index, s))
        else:
            entry = (t0, t0 + float(self.rng.uniform(*self.rest)), "rest", (here,))
        self.plan.append(entry)
        self.starts.append(entry[0])

    def pose(self, t: float) -> tuple[float, float, float]:
        """(x m, y m, angle rad) at time ``t`` seconds (as :meth:`PuckScript.pose` for times
        long past)."""
        while self.plan[-1][1] < t:
            self._extend()
        if forget(self.plan, self.starts, t):
            self.performed = [p for p in self.performed if p[1] >= t - HISTORY_S]
        t0, t1, kind, data = self.plan[max(bisect.bisect_right(self.starts, t) - 1, 0)]
        if kind == "rest":
            return data[0][0], data[0][1], self.angle
        if kind == "return":
            s = min_jerk((t - t0) / (t1 - t0))
            (x0, y0), (x1, y1) = data[0], self.home
            return x0 + (x1 - x0) * s, y0 + (y1 - y0) * s, self.angle
        start, index, speed = data
        g = self.gestures[index]
        tau = g[0, 0] + (t - t0) * speed
        return (start[0] + float(np.interp(tau, g[:, 0], g[:, 1])),
                start[1] + float(np.interp(tau, g[:, 0], g[:, 2])), self.angle)
