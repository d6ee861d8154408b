"""A figure standing near the table's top or bottom edge kept on the table through an action.

Actions rise and travel (a jump's highest part 0.04 m, a punch's 0.06 m above the standing
figure's top at 0.3 m tall, view 90,15): near the edge they left the table. The drawing is
offset along the table's y (metres) by the clip's own need, looked up over the action's
generalised time and eased in ``EASE_S`` before the part that needs it and out after (the
action's postures at ``SAMPLES`` times, with the weights it started with, placed where it
started). A figure that stays inside is drawn exactly where it was (no offset).
"""

from __future__ import annotations

import numpy as np

#: Seconds over which the drawing offset is eased in before it is needed and out after.
EASE_S = 0.4
#: Generalised times at which an action's postures are looked at when it starts.
SAMPLES = 32


def smooth(x: np.ndarray | float) -> np.ndarray:
    """Smoothstep of ``x`` clipped to 0-1 (0 -> 0, 1 -> 1, flat at both ends)."""
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def need(y: np.ndarray, height: float, margin: float) -> float:
    """Table-y offset (m) bringing drawn points ``y`` (m) ``margin`` inside a table ``height``
    deep; 0 when they lie inside or cannot fit."""
    lo, hi = float(y.min()), float(y.max())
    if hi - lo > height - 2.0 * margin:
        return 0.0
    if lo < margin:
        return margin - lo
    return height - margin - hi if hi > height - margin else 0.0


class EdgeLift:
    """The drawing offset (table y, m) of one character: planned when an action starts,
    eased out after it ends."""

    def __init__(self) -> None:
        self.clock: object | None = None        # the running action's clock it was planned for
        self.u = np.linspace(0.0, 1.0, SAMPLES)
        self.needs = np.zeros(SAMPLES)
        self.width_u = 1.0                      # EASE_S as generalised time
        self.seen = (0.0, 0.0)                  # generalised times the action ran through
        self.t0 = 0.0                           # seconds when it started
        self.lift = 0.0                         # the offset drawn now
        self.ended: tuple[float, float] | None = None   # (t, offset) when the action ended
        self.rest = 0.0                  # the need (m) of the posture the last action left
        self.rest_of: object | None = None   # that posture

    def plan(self, clock: object, needs: np.ndarray, duration: float, u: float,
             t: float) -> None:
        """Needs (m) at :attr:`u` of the action ``clock`` runs, ``duration`` seconds long,
        started at generalised time ``u``, time ``t`` (s)."""
        self.clock, self.needs, self.t0 = clock, np.asarray(needs, float), t
        self.width_u = EASE_S / max(duration, 1e-6)
        self.seen = (u, u)
        self.ended, self.rest, self.rest_of = None, 0.0, None

    def during(self, u: float, heading: int, t: float) -> float:
        """The eased offset at generalised time ``u`` running the ``heading`` way (+1 or -1):
        each sample's need, of the times run through or lying ahead, weighed down with its time
        distance (smoothstep over ``EASE_S``), the largest up and down taken. (Times behind the
        start left in: a spin kick started at 0.61 from 200,10 near the bottom was drawn
        0.05 m higher at once.)"""
        self.seen = (min(self.seen[0], u), max(self.seen[1], u))
        ahead = self.u > u if heading > 0 else self.u < u
        used = ahead | ((self.u >= self.seen[0]) & (self.u <= self.seen[1]))
        w = smooth(1.0 - np.abs(self.u - u) / self.width_u) * np.where(used, self.needs, 0.0)
        ease = float(smooth((t - self.t0) / EASE_S))
        return ease * float(w.max(initial=0.0) + w.min(initial=0.0))

    def after(self, t: float, rest: float) -> float:
        """The offset at time ``t`` (s) eased from where the last action left it to ``rest``
        (m), the need of the posture the action left where it rests. (Taken at once, a jump
        seen from 250,25 near the top moved every part 0.034 m in one frame as it ended.)"""
        if self.ended is None:
            self.ended = (t, self.lift)
        t0, lift = self.ended
        return float(lift + (rest - lift) * smooth((t - t0) / EASE_S))
