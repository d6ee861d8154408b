"""Two places read as one marker id: the puck and a print of its marker (or another puck
wearing the same id). The track follows one place; far readings of its id are followed as its
rival. A rival that moves while the track's place lies still is the puck (a print does not move
with a visitor's hand): the track takes it, and the place it leaves is a decoy whose readings
are no longer taken for the puck unless the track itself comes there.

Units: whatever the tracker uses (table metres by default), seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence, TypeVar

M = TypeVar("M")


@dataclass
class Rival:
    """Far readings of a track's id followed as one place: where it was first read (``x0``,
    ``y0``) and last (``x``, ``y``, at ``t``), and where the track was when it was first read
    (``tx``, ``ty``)."""

    x0: float
    y0: float
    x: float
    y: float
    t: float
    tx: float
    ty: float

    def moved(self) -> float:
        """How far the rival has moved since it was first read."""
        return math.hypot(self.x - self.x0, self.y - self.y0)


def follow(rival: Rival | None, x: float, y: float, t: float, reach: float, track: list[float],
           still: float) -> Rival:
    """The rival after a far reading at (x, y) at ``t``: the same rival moved there when within
    ``reach`` of its last place, else a new one. ``track``: the track's place now; once it is
    over ``still`` from where it was when the rival was first read, the rival's moves are
    counted from here."""
    if rival is None or math.hypot(x - rival.x, y - rival.y) > reach:
        return Rival(x, y, x, y, t, track[0], track[1])
    if math.hypot(track[0] - rival.tx, track[1] - rival.ty) > still:
        rival.x0, rival.y0, rival.tx, rival.ty = rival.x, rival.y, track[0], track[1]
    rival.x, rival.y, rival.t = x, y, t
    return rival


def screened(ms: Sequence[M], dists: Sequence[float], decoy: tuple[float, float], near: float
             ) -> tuple[list[M], list[float]]:
    """The readings ``ms`` (with ``x``, ``y``) and their distances from the track's prediction
    without those within ``near`` of the ``decoy`` (a print's place), unless within ``near``
    of the prediction too (the puck has come there)."""
    keep = [i for i, m in enumerate(ms) if dists[i] <= near
            or math.hypot(m.x - decoy[0], m.y - decoy[1]) > near]  # type: ignore[attr-defined]
    return [ms[i] for i in keep], [dists[i] for i in keep]
