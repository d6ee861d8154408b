"""Attract mode and the "one moment" screen: frame filters of the kiosk's loop.

:class:`Attract`: when no visitor has been seen for ``idle_s`` (no touch, and no puck put down or
moved by more than ``move_m``), scripted pucks (a :class:`~tabletop.plugins.scripted.ScriptedSource`
script: wandering mains for the reactors, gesture performers for the MOP characters) take the
place of the visitor's, reported ``coasting`` so the view draws them as rings, not as pucks on
the table. When a visitor arrives, every scripted puck the visitor also holds glides from its
scripted pose to the visitor's over ``handover_s`` (smoothstep), so a character never jumps; the
other scripted pucks leave. Frame ``status`` is ``"attract"`` while it plays.

:class:`OneMoment`: a source that has worked and has been down for ``grace_s`` (an unplugged
camera) sets the frame's ``status`` to ``"one_moment"`` until it is back; the view then shows the
calm waiting screen instead of frozen characters.

Both time themselves on the loop's clock (seconds), not on frame times: a frame's time is the
capture time of its newest input, which stands still while a camera is gone.
"""

from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path
from typing import Any, Callable

from tabletop.frames import Frame, Puck

Poses = Callable[[float], list[tuple[int, float, float, float]]]


def attract_performers(cfg: dict, table: tuple[float, float]) -> list[dict]:
    """Scripted performers for attract mode, one per MOP performer driven by a puck's path
    (``features: [dx, dy]``): it draws that performer's action templates (CSV ``t,dx,dy``) from
    a home spread along the table, so the MOP characters play their actions."""
    found: list[tuple[int, list]] = []
    read: dict[str, object] = {}    # each template read once, however many actions share it
    for e in cfg["engines"]:
        if e["kind"] != "mop":
            continue
        for p in e["performers"]:
            (inp, *more) = p["inputs"]
            if more or inp["kind"] != "puck" or list(inp["features"]) != ["dx", "dy"]:
                continue
            files = []
            for c in e["characters"]:
                for a in c["actions"]:
                    if (a["performer"] or c["performer"]) == p["name"]:
                        key = str(a["template"])
                        if key not in read:   # (the scripted build takes the rows read here)
                            read[key] = _gesture(a["template"])
                        if read[key] is not None:
                            files.append(read[key])
            if files:
                found.append((inp["id"], files))
    w, h = table
    return [{"puck": pid, "home": [w * (k + 1) / (len(found) + 1), h * 0.45], "gestures": files,
             "speed": [0.8, 1.3]} for k, (pid, files) in enumerate(found)]


def _gesture(template: Path) -> Any:
    """A MOP template as a scripted gesture (CSV ``t,dx,dy``; None if it is none): the table
    its config's load read while the file is as it was (no second read), else read now."""
    from tabletop.files import FileFormatError
    from tabletop.plugins.mop_files import Template
    from tabletop.plugins.scripted import gesture_of, read_gesture
    if isinstance(template, Template) and template.unchanged():
        cols, data, _ = template.content
        return (gesture_of(template, cols, data, template.read)
                if {"t", "dx", "dy"} <= set(cols) else None)
    try:
        return read_gesture(template)
    except FileFormatError:
        return None


def smoothstep(u: float) -> float:
    """0 -> 0, 1 -> 1 with zero slope at both ends; clipped outside [0, 1]."""
    u = min(1.0, max(0.0, u))
    return u * u * (3.0 - 2.0 * u)


def blend_angle(a: float, b: float, w: float) -> float:
    """From angle ``a`` toward ``b`` by fraction ``w`` the short way round (radians)."""
    d = math.remainder(b - a, math.tau)
    return math.remainder(a + w * d, math.tau)


class Attract:
    """Frame filter; see the module docstring. Times are the frames' (seconds)."""

    def __init__(self, poses: Poses, idle_s: float = 60.0, handover_s: float = 1.0,
                 move_m: float = 0.01, clock: Callable[[], float] = time.monotonic) -> None:
        self.poses, self.idle_s, self.handover_s, self.move_m = poses, idle_s, handover_s, move_m
        self.clock = clock
        self.last_visit: float | None = None
        self.active = False
        self.started = 0.0
        self._anchors: dict[int, tuple[float, float]] = {}
        self._handover: tuple[float, dict[int, tuple[float, float, float]]] | None = None
        self.sessions = 0

    def _visitor(self, frame: Frame) -> bool:
        """True when a visitor acts this tick: a touch, a puck put down or moved."""
        active = bool(frame.touches)
        seen = set()
        for p in frame.pucks:
            if p.state != "seen":
                continue
            seen.add(p.id)
            a = self._anchors.get(p.id)
            if a is None or math.hypot(p.x - a[0], p.y - a[1]) > self.move_m:
                self._anchors[p.id] = (p.x, p.y)
                active = True
        for pid in list(self._anchors):
            if pid not in seen:
                del self._anchors[pid]
        return active

    def idle_for(self, t: float) -> float:
        return 0.0 if self.last_visit is None else max(0.0, t - self.last_visit)

    def __call__(self, frame: Frame) -> Frame:
        t = self.clock()
        if self.last_visit is None:
            self.last_visit = t
            self._visitor(frame)
            return frame
        if self._visitor(frame):
            self.last_visit = t
            if self.active:
                self.active = False
                scripted = {pid: (x, y, a) for pid, x, y, a in self.poses(t - self.started)}
                self._handover = (t, scripted)
        elif not self.active and t - self.last_visit >= self.idle_s:
            self.active, self.started, self._handover = True, t, None
            self.sessions += 1
        if self.active:
            pucks = tuple(Puck(pid, x, y, a, state="coasting")
                          for pid, x, y, a in self.poses(t - self.started))
            return dataclasses.replace(frame, pucks=pucks, status=frame.status or "attract")
        if self._handover is not None:
            return self._hand_over(frame, t)
        return frame

    def _hand_over(self, frame: Frame, t: float) -> Frame:
        t0, scripted = self._handover  # type: ignore[misc]
        w = smoothstep((t - t0) / self.handover_s) if self.handover_s > 0 else 1.0
        if w >= 1.0:
            self._handover = None
            return frame
        pucks = []
        for p in frame.pucks:
            s = scripted.get(p.id)
            if s is None:
                pucks.append(p)
                continue
            pucks.append(dataclasses.replace(
                p, x=s[0] + w * (p.x - s[0]), y=s[1] + w * (p.y - s[1]),
                angle=blend_angle(s[2], p.angle, w)))
        return dataclasses.replace(frame, pucks=tuple(pucks))


class OneMoment:
    """Frame filter: ``status = "one_moment"`` while a source that has worked is down."""

    def __init__(self, grace_s: float = 1.0, clock: Callable[[], float] = time.monotonic) -> None:
        self.grace_s, self.clock = grace_s, clock
        self._worked: set[str] = set()
        self._down_since: dict[str, float] = {}
        self.active = False

    def __call__(self, frame: Frame) -> Frame:
        waiting = False
        now = self.clock()
        for h in frame.health:
            if h.ok:
                self._worked.add(h.name)
                self._down_since.pop(h.name, None)
            elif h.name in self._worked:
                since = self._down_since.setdefault(h.name, now)
                waiting = waiting or now - since >= self.grace_s
        self.active = waiting
        return dataclasses.replace(frame, status="one_moment") if waiting else frame
