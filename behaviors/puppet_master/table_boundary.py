"""Where a generation step may end on the table (paper section 4.4.1's target carried onto the
table; :mod:`generation` steps toward it).

:func:`fit_target` moves a target onto the table at its distance from the main,
:func:`turn_off_edges` turns a step off the edges near them, :func:`keep_on_table` shortens a
step that would leave it, :func:`table_reach` measures the way to an edge; out of the other
characters' discs and the main's way: :mod:`apart`. Positions in table metres, tables as
(x0, y0, x1, y1).
"""

from __future__ import annotations

import functools
import math


def clamp_to_table(x: float, y: float,
                   table: tuple[float, float, float, float]) -> tuple[float, float]:
    """Nearest point of the table rectangle (x0, y0, x1, y1)."""
    x0, y0, x1, y1 = table
    return min(max(x, x0), x1), min(max(y, y0), y1)


@functools.lru_cache(maxsize=8)
def _bearings(count: int) -> tuple[tuple[float, float], ...]:
    """(cos, sin) of ``count`` bearings evenly round the circle (made once per count)."""
    return tuple((math.cos(math.tau * k / count), math.sin(math.tau * k / count))
                 for k in range(count))


def fit_target(mx: float, my: float, tx: float, ty: float, rx: float, ry: float,
               table: tuple[float, float, float, float],
               step_deg: float = 5.0) -> tuple[float, float]:
    """Target (tx, ty) moved onto the table, keeping its distance from the main at (mx, my).

    A demonstrated relation that does not fit the table here (the main is near an edge) keeps
    what matters most for a relation, its distance, and takes the point at that distance on the
    table nearest to the reactor at (rx, ry) (bearings every ``step_deg``). A keep-away
    character pinned at an edge so slides along it to the near side instead of letting the
    main reach it (choosing the smallest turn of the bearing instead made it run back and forth
    under the main as that side flipped); a follower behind a main at the edge walks beside it.
    If no bearing fits (the distance exceeds the table), the nearest table point.

    The bearings are searched wherever the main is, also in the band between the live table's
    edge and the character's edge margin (a visitor that has followed the afraid character
    toward an edge). Searched only with the main on the margin table, such a target was
    clamped, toward the main: chased (seeds 0-5, 8-13, 26-31), 24% of its steps within 0.2 m
    of the visitor had their target shrunk toward it, by 0.10 m on average (now none; within
    0.2 m on 29% of its steps instead of 34%). bench/fidelity.py, seeds 0-5 / 8-13 /
    26-31: met 668 / 667 / 665 -> 672 / 673 / 659 of 720, the engine's alone 9 / 15 / 17 -> 8 /
    15 / 17, chased 47 / 41 / 43 -> 45 / 45 / 41 of 48 (the engine's 0 / 7 / 2 -> 1 / 3 / 4);
    the afraid character's misses 26 / 24 / 25 -> 22 / 18 / 31, the other characters the
    same to the last digit; --perturb 2 (three runs per set) 2002 / 1993 / 2005 -> 2011 / 2010
    / 1985 of 2160, the engine's alone 32 / 43 / 47 -> 32 / 43 / 49 (the afraid character's
    misses 78 / 78 / 66 -> 69 / 61 / 86: seeds 26-31 lose facing, orbit and speed on the open
    paths). Its mean distance chased 0.292 -> 0.302 m (at an edge 0.133 ->
    0.123; its demonstration 0.366 m, its designer 0.39). The afraid character alone with
    Params.relative_motion x 1 +- 0.001, 1 +- 0.002 (four runs of those 18 seeds): open paths
    1435 -> 1443 of 1728 met, chased 527 -> 521 of 576 (facing 21 -> 24 misses, caught once),
    distance chased 0.293 -> 0.299 m: the distance gained is small and the chase's thresholds
    do not follow it. The rest of the gap opens while the visitor does not chase (the
    distance's rate per visitors.Pursuer mode, against its designer's: pulling back +0.12
    against +0.21 m/s, wandering +0.013 against +0.030, chasing -0.039 against -0.054): its
    places are held relative to the main, so it follows a visitor that backs off. Measured
    (unperturbed, 18 seeds; open paths of 432 / chased of 144 met, distance chased, against
    361 / 131 / 0.302 m): the main's step away from it not carried 349 / 132 / 0.306; nor
    the drift correction's part toward a main that backs off 343 / 128 / 0.316; only that part
    343 / 133 / 0.310; both only at moments whose demonstrated main stood 355 / 134 / 0.298.
    Not used: the open paths lose orbit and facing.

    It is also what turns the afraid character's flight into circling when a visitor chases
    it toward an edge (bench/fidelity.py's pursuit: orbit 0.41-0.51 rad/s against 0.335, missed
    on 5 of 7 seeds). Traced on seeds 0 and 2 (steps 0.2-0.45 m from the visitor while it
    closes): the flight target lies beyond the edge and is moved onto the table on 52-100% of
    them, by 0.17-0.21 m round the visitor; the drift correction toward it (the share
    Params.relative_motion of the way) is then 0.36-0.67 m/s sideways, the step is capped at
    the demonstrated speed (0.24-0.29 m/s), and what is left of the flight is 0.00-0.08 m/s
    away from the visitor against 0.11-0.32 demonstrated: the visitor comes within 0.2 m a
    quarter of the time (6% in the demonstration), where the same sideways speed is a faster
    orbit. Measured remedies (Python step, pursuit thresholds on seeds 0-5 / 7, against 40 /
    7): the table point nearest the target instead 26 / 4; no fitting (keep_on_table slides
    the step) 28 / 6; the correction toward a moved target at most the demonstrated step length
    there, in a place held in the world 39 / 7 (orbit 0.34-0.53), in both place frames 38 / 7; the
    flight kept whole under the cap and the correction given what is left 41 / 7 (orbit 0.38-0.60).
    None kept: the matched moments are themselves slow flights (0.42-0.45 m from the main,
    0.19-0.24 m/s, where the live character is at 0.2-0.45 m), so the flight left is short
    whatever the correction does. Measured as well (same figures): the part cut off carried
    along the edge away from the visitor 28 / 5 (caught: 0.14-0.32 m from it); the fit at the
    live distance where it is nearer than the matched one 34 / 7; onto the table shrunk by
    0.05 / 0.1 / 0.2 m 40 / 40 / 39 (7 / 7 / 6); the bearing point nearest the reactor less 1x /
    2x its room to an edge (at most 0.2 m) 41 / 39 (7 / 7; seeds 8-19: 79 -> 78 / 81 of 96),
    edge share 0.24-0.71 but orbit unchanged; the correction toward a moved target only along
    the bearing 29 / 7 (pinned at the edge); the catch-up from the unmoved target 37 / 7; a
    world-held place nearer than its moment at least as fast as the demonstration at that
    distance while its main closed in (median 0.17-0.26 m/s) 41 / 7 (seeds 8-19: 79 -> 75).
    The orbit (0.41-0.51 rad/s) fell only where the visitor caught the character: the turn
    round the visitor is the dodge that keeps it uncaught; between 0.3 and 0.45 m the matched
    moments' own outward step is 0.04-0.07 m/s against the demonstration's 0.12 there.

    The table passed in is Reactor.target_table: the live table less the demonstrated
    character's edge margin (Params.edge_percentile), for a character that sets one. Chased by
    the unseen visitor, the afraid character was at an edge (within 0.1 m) 34-59% of the time
    (seeds 0-5, mean 0.45; its designer's own 5-13%). Traced at the edge (seeds 0-5): the live
    character had 0.05 m of room behind it along the bearing from its main (0.22 m away),
    the matched moments 0.185 m, and half of them were coherence choices, which the room does
    not enter; their targets, carried onto the live main, lay beyond the edge or in the band
    along it, and fitted onto the very edge they drew the character where its demonstration
    never was (distance to an edge: 1st percentile 0.07 m, median 0.157 m), and keep_on_table
    then slid it along the edge. Plotted, the designer's own character circles the table about
    0.15 m in from its edges, the generated one ran along them. Fitted onto the table less the
    median distance (bench/fidelity.py, open paths met / engine-only misses / pursuit met /
    time at an edge chased, seeds 0-5; 7; 8-13; 14-19, against the room feature w_room 2
    before it): 664 / 16 / 42 / 0.19 (664 / 17 / 46 / 0.45); 112 / 3 / 8 / 0.04 (110 / 2 / 6
    / 0.34); 651 / 29 / 42 / 0.08 (656 / 31 / 39 / 0.36); 655 / 27 / 39 / 0.17 (654 / 26 /
    38 / 0.39). The 45th and 55th percentiles (a few mm either way, the re-matching's noise):
    655 / 18 / 44 / 0.15 and 658 / 17 / 46 / 0.19 on seeds 0-5, 640 / 32 / 41 / 0.15 and 649
    / 29 / 41 / 0.10 on 8-13. With the room feature kept as well (w_room 2), seeds 0-5 / 7 /
    8-13: 653 / 109 / 645 met, pursuit 43 / 8 / 44, at an edge 0.10 / 0.12 / 0.09: the open
    paths' lost checks are the afraid character's facing and orbit, which its own designer
    misses there (it leaves the walls and watches a main that never chases it). Measured as
    well (the afraid character alone, open paths of 144 and pursuit of 48 on seeds 0-5, with
    the room; 120 / 46 / 0.45 without a margin): the table shrunk for the whole step (target
    and keep_on_table) by 0.07 / 0.1 m 111 / 41 / 0.19 and 111 / 46 / 0.005 (a wall at the
    measure's own 0.1 m); the margin only for targets off the table 117-119 / 40-43 / 0.29-0.34;
    only with the main within 0.5 m 109 / 47 / 0.13, or closing in on the character 107-116 /
    44-46 / 0.13-0.18 (no better than the margin everywhere).
    """
    x0, y0, x1, y1 = table
    if x0 <= tx <= x1 and y0 <= ty <= y1:
        return tx, ty
    rho = math.hypot(tx - mx, ty - my)
    best: tuple[float, float, float] | None = None
    if rho > 1e-9:
        for c, s in _bearings(int(round(360.0 / step_deg))):
            px, py = mx + rho * c, my + rho * s
            if x0 <= px <= x1 and y0 <= py <= y1:
                d = (px - rx) ** 2 + (py - ry) ** 2
                if best is None or d < best[0]:
                    best = (d, px, py)
    if best is not None:
        return best[1], best[2]
    return clamp_to_table(tx, ty, table)


def keep_on_table(rx: float, ry: float, sx: float, sy: float,
                  table: tuple[float, float, float, float]) -> tuple[float, float]:
    """A step from (rx, ry) that stays on the table.

    The paper's features ignore world coordinates, so nothing in the match knows the table: a
    fleeing reactor would run off it. A step that would cross an edge loses its outward part and
    keeps its length along the edge (a cornered character slides away along the wall instead
    of stopping there); the result is clamped to the table.

    Against a visitor chasing it (bench/fidelity.py's pursuit, seeds 0-5) the afraid character
    spends 44-79% of its steps within 0.1 m of an edge (``edge_share``; demonstration 37%, its
    designer's own hand 18-59%). Two extensions of the paper's model that bring the table in
    were measured (thresholds met on seeds 0-5 / held-out seed 7, open paths and pursuit,
    against 623 / 107 and 40 / 7): the reactor's distance to the nearest edge (clipped at
    0.2 m; the demonstration's edges its bounds) as a seventh situation feature, weighed as the
    relative position: 620 / 103 and 40 / 6, the edge share unchanged (0.49-0.66); weighed by
    its own inverse spread: 610 / 104 and 42 / 8. The step's part toward an edge held to the
    edge's distance over the demonstrated reactor's median time to an edge (0.38-1.7 s), the
    rest along it: edge share 0.18-0.43, 625 / 108 and 39 / 7, but the character is then
    caught in the open (mean distance to the visitor 0.29-0.38 -> 0.23-0.32 m on every seed,
    against 0.41 demonstrated); the same only within 0.2 m of an edge: 621 / 105 and 41 / 7.
    Neither is used. What makes its orbit is :func:`fit_target` (see there).

    Traced on the pursuit of seed 0 (24 of its 40 s at an edge): the matched moments flee
    straight away from the visitor (they were 0.15 m from an edge in the demonstration, 0.42 m
    from their main), this clamp turns each into a slide, and the character runs along the
    edges; the longest spell (13.4 s) was a corner, see :func:`apart.keep_apart`. Two more ways of
    bringing the table in were measured (bench/fidelity.py, open paths met on seeds 0-5 / 7 /
    8-13 against 659 / 109 / 651, pursuit against 41 / 8 / 38, mean time at an edge under
    pursuit against 0.533 / 0.48 / 0.500). In BestMatch, where the best window's
    continuation (its reactor's way over the next 0.5 s, along and across the bearing from its
    main, turned to the live bearing) leaves the table, the best window whose continuation
    stays on it within 1.5x the best distance (at an edge the best one's left in 61% of the
    steps of seed 0; the best fitting one cost 1.21x, 90th percentile 2.1x): 642 / 109 / 633,
    pursuit 45 / 6 / 42, at an edge 0.452 / 0.32 / 0.448; over 1 s 641 / 109 / 632; within
    1.2x 648 / 108 / 630 (0.462 / 0.36 / 0.488); over 0.25 s 645 / 105 / 641; only while the
    main closes in over 0.5 s 644 / 110 / 631 (0.415 / 0.56 / 0.423). The afraid character's
    own misses on the open paths rose 22 -> 29-35 (orbit and facing) and 28 -> 33-47 on seeds
    8-13. A step that would cross an edge turned across the bearing from the main, to the
    table's side (as its designer escapes round the hand): at an edge 0.43 -> 0.59 (seed 0,
    40 s pursuit), 0.73 -> 0.77 (seed 20). None is used.
    """
    x0, y0, x1, y1 = table
    length = math.hypot(sx, sy)
    nx, ny = rx + sx, ry + sy
    changed = False
    if nx < x0 or nx > x1:
        sx = 0.0
        changed = True
    if ny < y0 or ny > y1:
        sy = 0.0
        changed = True
    if changed:
        rest = math.hypot(sx, sy)
        if rest > 1e-12:
            sx, sy = sx * length / rest, sy * length / rest
    nx, ny = clamp_to_table(rx + sx, ry + sy, table)
    return nx - rx, ny - ry


EDGE_TURN = 0.75    # the inward pull at the very edge, against the step's unit direction


def turn_off_edges(rx: float, ry: float, sx: float, sy: float,
                   table: tuple[float, float, float, float], band: float
                   ) -> tuple[float, float]:
    """The step (sx, sy) from (rx, ry) turned away from the table's edges within ``band``
    metres of them, its length kept: its direction plus an inward pull growing from 0 at
    ``band`` from an edge to EDGE_TURN at the edge (both axes at a corner). ``band`` is the
    character's edge margin (Behavior.edge_margin, the median distance to an edge in its
    demonstration); 0 turns nothing.

    The matched moments flee straight away from the main and do not see the table: chased
    toward an edge, a character not turned runs into it and :func:`keep_on_table` slides it
    along the edge (the same length, no room behind it); its designer turns off the walls before
    reaching them (designers.afraid: flight plus 1.5x a push growing from 0.2 m). Chased by the
    unseen visitor (bench/fidelity.py's pursuit, seeds 0-5, 8-13, 26-31, mean over the 18), the
    afraid character's time within 0.1 m of an edge against its designer's 0.066: EDGE_TURN 0 0.123,
    0.5 0.070, 0.75 0.049, 1.0 0.045, 1.5 0.025 (1.5 over 0.2 m: 0.009); pursuit thresholds
    met 131 / 130 / 137 / 130 / 130 (135) of 144 (designer 119), the mean distance to the
    visitor 0.302 / 0.299 / 0.303 / 0.296 / 0.289 m (designer 0.395): off the edges it is
    not caught nearer, but the distance does not follow, its gap opens while the visitor pulls
    back (see fit_target). Turning only steps heading outward (EDGE_TURN 0.75): 0.070, 125,
    0.292 m. bench/fidelity.py --seeds 0-5 / 8-13 / 26-31 with 0.75: open paths met 673 / 675
    / 661 -> 674 / 669 / 661 of 720 (the engine's alone 7 / 12 / 15 -> 8 / 13 / 15), pursuit
    45 / 45 / 41 -> 47 / 45 / 45 of 48; the other characters the same to the last digit, the
    afraid character's misses 22 / 18 / 31 -> 21 / 24 / 31. With --perturb 2 (three runs per
    set) 2019 / 2016 / 1990 -> 2015 / 2002 / 1995 of 2160, the engine's alone 23 / 34 / 44 ->
    22 / 39 / 43, the afraid character's misses 69 / 61 / 86 -> 73 / 75 / 81 (seeds 8-13 lose
    facing, speed and orbit on the open paths, where its designer misses them too); with 0.5
    1999 / 1998 / 2005, its misses 89 / 79 / 71, pursuit 45 / 43 / 42.
    """
    if band <= 0.0:
        return sx, sy
    x0, y0, x1, y1 = table
    length = math.hypot(sx, sy)
    wx = max(0.0, 1.0 - (rx - x0) / band) - max(0.0, 1.0 - (x1 - rx) / band)
    wy = max(0.0, 1.0 - (ry - y0) / band) - max(0.0, 1.0 - (y1 - ry) / band)
    if length <= 1e-12 or (wx == 0.0 and wy == 0.0):
        return sx, sy
    ux, uy = sx / length + EDGE_TURN * wx, sy / length + EDGE_TURN * wy
    n = math.hypot(ux, uy)
    if n <= 1e-12:
        return sx, sy
    return length * ux / n, length * uy / n


def table_reach(x: float, y: float, ux: float, uy: float,
                table: tuple[float, float, float, float]) -> float:
    """Distance (metres) from (x, y) along the unit direction (ux, uy) to the table's edge
    (inf along no edge; negative where (x, y) is already beyond the edge it heads for)."""
    x0, y0, x1, y1 = table
    reach = math.inf
    if ux > 0.0:
        reach = min(reach, (x1 - x) / ux)
    elif ux < 0.0:
        reach = min(reach, (x0 - x) / ux)
    if uy > 0.0:
        reach = min(reach, (y1 - y) / uy)
    elif uy < 0.0:
        reach = min(reach, (y0 - y) / uy)
    return reach
