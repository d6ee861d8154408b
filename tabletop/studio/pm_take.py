"""What a Puppet Master take tells the designer before it is trained: whether its pucks
moved at all (:func:`motionless`), and how long a puck the take needs went unseen while it
was recorded (:class:`Unseen`, which a MOP take's target keeps too)."""

from __future__ import annotations

import math

import numpy as np

from tabletop.frames import InputError

STILL_M = 0.01
"""A puck that never comes this far (metres) from where the take began has not moved: the
camera's jitter on a resting puck is under a millimetre (0.03 mm on the synthetic camera at
640x360), a demonstrated reaction moves tens of centimetres."""

STILL_RAD = 0.2
"""Nor turned this far (radians, about 11 degrees): a reactor that only turns to look at the
main is a demonstration."""


def reach(demo: np.ndarray, cols: tuple[int, int, int]) -> tuple[float, float]:
    """How far (metres) and how much (radians) one puck of ``demo`` (columns ``cols``: x, y,
    direction) got from its first pose."""
    x, y, a = (demo[:, c] for c in cols)
    far = float(np.max(np.hypot(x - x[0], y - y[0])))
    turn = float(np.max(np.abs(np.angle(np.exp(1j * (a - a[0]))))))
    return far, turn


def motionless(demo: np.ndarray, main_puck: int, react_puck: int) -> None:
    """InputError when neither puck of ``demo`` (n, 7: t, main x y dir, react x y dir) moved
    or turned, or the reactor's did not while the main moved (the reactor puck forgotten on
    the table): either take trains a character that stands still whatever the visitor does.
    A still main with a reactor walking off is a demonstration."""
    if len(demo) == 0:
        return
    main, react = reach(demo, (1, 2, 3)), reach(demo, (4, 5, 6))
    still = [far < STILL_M and turn < STILL_RAD for far, turn in (main, react)]
    if all(still):
        raise InputError(f"neither puck moved (puck {main_puck} {main[0] * 100:.1f} cm, puck "
                         f"{react_puck} {react[0] * 100:.1f} cm from where the take began)")
    if still[1]:
        raise InputError(f"the reactor, puck {react_puck}, never moved ({react[0] * 100:.1f} "
                         f"cm from where the take began, turned {react[1]:.2f} rad): its "
                         "character would stand still")


class Unseen:
    """Seconds of a take's recording during which each puck it needs was missing from the
    frame (a puck is in the frame while the tracker coasts it, so only one lost for longer
    than ``tracking.coast_s`` counts), or each other input a MOP performer needs (named:
    "finger", "stream arm"); those stretches are not in the take."""

    SAY_FRACTION = 0.05
    """Said once a puck was missing for this share of the recording or more."""

    def __init__(self) -> None:
        self.missing: dict[int | str, float] = {}   # puck id or input name: seconds
        self.needed: dict[int | str, float] = {}    # seconds each was needed (else: total)
        self.total = 0.0
        self._t = math.nan

    def tally(self, t: float, missing: list[int | str],
              needed: list[int | str] | None = None) -> None:
        """A recorded frame at ``t`` (seconds) without ``missing`` (puck ids, input names) of
        those it ``needed`` (None: all, the whole recording). A sequential take needs its
        main puck in the main part alone and its reactor puck in the reaction alone: a
        reactor puck lost 0.6 s of a 5.0 s reaction was said "of 10.1 s", both parts."""
        dt = t - self._t if t > self._t else 0.0      # (nan on the first frame: 0)
        self._t = t
        self.total += dt
        for p in missing:
            self.missing[p] = self.missing.get(p, 0.0) + dt
        for p in needed or ():
            self.needed[p] = self.needed.get(p, 0.0) + dt

    def pause(self) -> None:
        """The recording pauses (between a sequential take's parts): no time passes for it."""
        self._t = math.nan

    def words(self) -> str:
        """"puck 2 unseen 4.6 s of 9.3 s" for each puck (or "finger", ...) missing long
        enough, pucks first, or ""."""
        def order(p: int | str) -> tuple[int, int, str]:   # puck 2 before puck 10
            return (0, p, "") if isinstance(p, int) else (1, 0, p)

        of = {p: self.needed.get(p, self.total) for p in self.missing}
        return ", ".join(f"{f'puck {p}' if isinstance(p, int) else p} unseen {s:.1f} s of "
                         f"{of[p]:.1f} s"
                         for p, s in sorted(self.missing.items(), key=lambda m: order(m[0]))
                         if of[p] > 0 and s >= self.SAY_FRACTION * of[p])

    def note(self) -> str:
        """What the trained line adds: "; puck 2 unseen 4.6 s of 9.3 s (left out)", or ""."""
        said = self.words()
        return f"; {said} (left out)" if said else ""
