"""Reactors of one table stepped together: every reactor plans its tick against the others'
previous shown poses, so no order among them decides who yields, then the planned ends are
moved apart jointly (:func:`apart_together`), each body by its share. Positions in table
metres, tables as (x0, y0, x1, y1), times in seconds.

Stepped in turn, each against the others' latest shown poses, the later of two yielded, and
where both fled at full pace the shown pose's pace cap left a later one closing in within the
frame; a step going round a body left its shown pose behind, blocked by the others' shown
bodies. Three / two reactors of one main (0.08 m bodies; unseen closed-loop scenes, 0.6 x 0.4
to 3.0 x 0.5 m, 30-60 Hz, five characters x 36 seeds each of 12-47 / 48-83 / 84-119), least
gap over the size: three 0.933 / 0.954 / 0.949 -> 0.997 / 0.998 / 0.983, two 0.907 / 0.943 /
0.953 -> 1.000 / 0.996 / 1.000; the shown pose behind its step, most (largest steps): three
9.6 / 8.1 / 7.8 -> 1.4 / 1.6 / 1.7 (frames over two steps 0.03% / 0.02% / 0.004% -> none),
two 1.4 / 1.3 / 1.7 -> 1.0 / 1.0 / 1.0; the shown move never over the largest step's pace.
Share of frames inside the main's disc: three 0.0589 / 0.0575 / 0.0600 -> 0.0574 / 0.0567 /
0.0586, two 0.0636 / 0.0632 / 0.0641 -> 0.0641 / 0.0627 / 0.0639; its least over the disc (one
frame of 36 scenes) mixed: three 0.014 / 0.003 / 0.005 -> 0.007 / 0.023 / 0.001, two 0.016 /
0.007 / 0.005 -> 0.003 / 0.014 / 0.009 (the bodies win over the main's disc, the stated order).
Seeds 120-155, three / two: least gap 0.954 / 0.934 -> 0.996 / 1.000, behind 8.5 / 1.2 -> 1.6 /
1.0, inside 0.0595 / 0.0646 -> 0.0584 / 0.0671 (two of one main both yield now, where the first
listed moved as if alone).

Not used: the shown poses alone moved apart, the steps planned against the previous tick as
here (three, seeds 12-47: least 0.748, shown pose 17.2 steps behind); the steps' ends moved
apart once a tick, not after each round of steps (the first of two steps in a frame left
overlapping: the afraid ones 0.903); pairs held by an edge not sliding along it (three, seeds
48-83: 0.933, two afraid ones in a corner); the main's disc held in the joint pass too (two,
seeds 12-47: least 1.000 -> 0.750, the shown pose 3.8 steps behind; the bully's least over its
disc 0.003 -> 0.079). A point's room cut where its push goes deeper into its own main's disc,
its partner taking the rest (seeds 12-47 / 48-83 / 84-119 / 120-155): share inside the disc,
three 0.0574 / 0.0567 / 0.0586 / 0.0584 -> 0.0556 / 0.0565 / 0.0589 / 0.0589, two 0.0641 /
0.0627 / 0.0639 / 0.0671 -> 0.0657 / 0.0639 / 0.0670 / 0.0652; least over the disc, three
0.007 / 0.023 / 0.001 / 0.006 -> 0.002 / 0.006 / 0.000 / 0.004, two 0.003 / 0.014 / 0.009 /
0.009 -> 0.003 / 0.006 / 0.021 / 0.009; least gap three 0.998 / 0.983 / 0.996 -> 0.989 / 0.996
/ 0.974 (48-83 / 84-119 / 120-155), two 1.000 -> 0.998 (84-119). The cut given up where the
pair's cut rooms cannot take the overlap: shares inside within 0.0004 of the cut's (two 0.0658 /
0.0637 / 0.0670 / 0.0648), least over the disc the same, least gap three 0.991 / 0.989 / 0.996
/ 0.996, two 1.000 / 0.996 / 0.999 / 1.000. A point on or in its main's disc pushed toward the
main sliding along the disc's tangent instead (or along an edge holding it, whichever way the
disc and the edges leave gains most of the push), cut at the disc's edge from outside, both
given up where the pair cannot take the overlap: pushes taking an end deeper into its disc
(seeds 12-23, five characters) two 377 -> 23, three 889 -> 29, but these are at most 0.0028 /
0.0043 of the reactor frames, and the share inside stays within the noise (each body's half
0.5 -> 0.5001 or 0.4999, which means nothing, moves a set's share by up to 0.0016): two 0.0636
/ 0.0616 / 0.0627 / 0.0664 -> 0.0636 / 0.0620 / 0.0644 / 0.0639, three 0.0566 / 0.0560 /
0.0582 / 0.0575 -> 0.0568 / 0.0564 / 0.0578 / 0.0580 (12-47 / 48-83 / 84-119 / 120-155); the
least over the disc (one frame) swings 0.000 - 0.016 under those null changes, and with three
it is the playful friend's own darts (0.000 - 0.008 with or without).
"""

from __future__ import annotations

import math
from typing import Sequence

from behaviors.puppet_master.engine import Reactor
from behaviors.puppet_master.apart import EDGE_EPS
from behaviors.puppet_master.table_boundary import clamp_to_table, table_reach

# joint passes over the overlapping pairs (apart_together), and the least share of the push a
# point held by an edge gains sliding along it (_way): first choices, not tuned
TOGETHER_PASSES = 8
SLIDE_GAIN = 0.2


def apart_together(xy: list[list[float]], least: Sequence[Sequence[float]],
                   room: list[float], table: tuple[float, float, float, float],
                   passes: int = TOGETHER_PASSES) -> None:
    """Moves the points ``xy`` (n of [x, y], in place) out of each other's discs: a pair
    nearer than ``least[i][j]`` metres is pushed apart along the line between them, each by
    half the overlap, or more where the other is held by the table's edge or has no ``room``
    left (metres each point may still move, spent in place). Every pair is read from the same
    positions in a pass and the pushes summed, so the points' order decides nothing."""
    n = len(xy)
    for _ in range(passes):
        moves = [[0.0, 0.0] for _ in range(n)]
        moved = False
        order = sorted(range(n), key=lambda k: (xy[k][0], xy[k][1]))   # by place, not index
        for a, i in enumerate(order):
            xi, yi = xy[i]
            for j in order[a + 1:]:
                dx, dy = xy[j][0] - xi, xy[j][1] - yi
                d = math.hypot(dx, dy)
                over = least[i][j] - d
                if over <= 1e-12:
                    continue
                if d < 1e-9:       # one spot: apart along x (the table's long side)
                    ux, uy = 1.0, 0.0
                else:
                    ux, uy = dx / d, dy / d
                wi = _way(xi, yi, -ux, -uy, room[i], table)
                wj = _way(xy[j][0], xy[j][1], ux, uy, room[j], table)
                mi = min(0.5 * over, wi[3])
                mj = min(over - mi, wj[3])
                mi = min(over - mj, wi[3])
                if mi <= 0.0 and mj <= 0.0:
                    continue
                moves[i][0] += wi[0] * mi / wi[2]
                moves[i][1] += wi[1] * mi / wi[2]
                moves[j][0] += wj[0] * mj / wj[2]
                moves[j][1] += wj[1] * mj / wj[2]
                moved = True
        if not moved:
            break
        for i in range(n):
            mx, my = moves[i]
            m = math.hypot(mx, my)
            if m <= 0.0:
                continue
            if m > room[i]:
                mx, my, m = mx * room[i] / m, my * room[i] / m, room[i]
            room[i] -= m
            xy[i][0], xy[i][1] = clamp_to_table(xy[i][0] + mx, xy[i][1] + my, table)


def _way(x: float, y: float, wx: float, wy: float, room: float,
         table: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """How a point at (x, y) pushed along the unit (wx, wy) moves: the unit direction, the
    separation gained per metre along it, and the separation it can gain (within ``room``
    metres). Held by an edge, it slides along that edge (a puck pushed against a wall), where
    that gains at least ``SLIDE_GAIN`` of the push."""
    reach = table_reach(x, y, wx, wy, table)
    if reach > EDGE_EPS:
        return wx, wy, 1.0, max(0.0, min(room, reach))
    x0, y0, x1, y1 = table
    if (x <= x0 + EDGE_EPS and wx < 0.0) or (x >= x1 - EDGE_EPS and wx > 0.0):
        wx = 0.0
    if (y <= y0 + EDGE_EPS and wy < 0.0) or (y >= y1 - EDGE_EPS and wy > 0.0):
        wy = 0.0
    gain = math.hypot(wx, wy)
    if gain < SLIDE_GAIN:
        return 1.0, 0.0, 1.0, 0.0
    wx, wy = wx / gain, wy / gain
    return wx, wy, gain, gain * max(0.0, min(room, table_reach(x, y, wx, wy, table)))


def update_together(reactors: Sequence[Reactor], t: float,
                    mains: Sequence[tuple[float, float, float]], bodies: Sequence[float],
                    table: tuple[float, float, float, float],
                    obstacles: Sequence[list[tuple[float, float, float]]] | None = None
                    ) -> list[tuple[float, float, float]]:
    """One tick of several reactors at time ``t``: each fed its main sample (``mains``, one
    per reactor) against the others' shown poses of the previous tick (``bodies``: their
    sizes, metres; two keep half the sum apart); the ends of the steps made moved apart
    together (Reactor.shift), then the shown poses, each at most the rest of its largest
    step's pace. ``obstacles``: each reactor's others (x, y, least distance m) as of the
    previous tick, where the caller keeps them (default: the others' last shown poses).
    Returns the shown poses (x, y, look)."""
    n = len(reactors)
    before = [r._shown if r.started else None for r in reactors]
    least = [[0.5 * (bodies[i] + bodies[j]) for j in range(n)] for i in range(n)]
    steps = []
    for i, r in enumerate(reactors):
        if obstacles is not None:
            r.obstacles = list(obstacles[i])
        else:
            r.obstacles = sorted((p[0], p[1], least[i][j])
                                 for j, p in enumerate(before) if j != i and p is not None)
        steps.append(r.stepping(t, *mains[i]) if r.started else iter(()))
    fresh = [not r.started for r in reactors]
    if any(fresh):         # those starting now take their places, then move apart together
        for r, m, f in zip(reactors, mains, fresh):
            if f:
                r.start(t, *m)
        starts = [list(r.pose[:2]) if r.started else [math.nan] * 2 for r in reactors]
        planned = [p[:] for p in starts]
        apart_together(starts, least, [math.inf if f else 0.0 for f in fresh], table)
        for r, m, f, p, q in zip(reactors, mains, fresh, starts, planned):
            if f and p != q:
                r.start(t, *m, at=(p[0], p[1]))
    # the obstacles as rows once a tick per reactor, for its steps and display (as update)
    rows = [r._obstacle_array() if r.compiled else None for r in reactors]
    going = [True] * n
    try:
        for r, k in zip(reactors, rows):
            r._obstacle_rows = k
        while any(going):      # the reactors' k-th steps of this tick, then their ends apart
            moved = []
            for i in range(n):
                if going[i]:
                    going[i] = next(steps[i], None) is not None
                moved.append(going[i])
            if any(moved):
                ends = [list(r.pose[:2]) for r in reactors]
                planned = [e[:] for e in ends]
                apart_together(ends, least, [math.inf if m else 0.0 for m in moved], table)
                for r, e, p in zip(reactors, ends, planned):
                    if (e[0], e[1]) != (p[0], p[1]):
                        r.shift(e[0] - p[0], e[1] - p[1])
    finally:
        for r in reactors:
            r._obstacle_rows = None
    shown = [list(r.shown_at(t, k)) for r, k in zip(reactors, rows)]
    room = []
    for r, p, s in zip(reactors, before, shown):
        if p is None:
            room.append(math.inf)
            continue
        pace = r.behavior.largest_step * max(t - p[2], 0.0) / r.dt
        room.append(max(0.0, pace - math.hypot(s[0] - p[0], s[1] - p[1])))
    xy = [s[:2] for s in shown]
    apart_together(xy, least, room, table)
    out = []
    for r, s, p in zip(reactors, shown, xy):
        if (p[0], p[1]) != (s[0], s[1]):
            r._shown = (p[0], p[1], t)
            r._lagging = True
        out.append((p[0], p[1], s[2]))
    return out

