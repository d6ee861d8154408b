"""Where a generation step may end: on the table and out of the other characters' discs
(paper section 4.4.1's target carried onto the table; :mod:`generation` steps toward it).

:func:`fit_target` moves a target onto the table at its distance from the main,
:func:`turn_off_edges` turns a step off the edges near them, :func:`keep_on_table` shortens a
step that would leave it, :func:`keep_apart` pushes a position
out of other characters' discs as far as the table lets it, :func:`out_of_way` out of the way
a fast main is about to take. Positions in table metres, tables
as (x0, y0, x1, y1).
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
    edges; the longest spell (13.4 s) was a corner, see :func:`keep_apart`. Two more ways of
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


def keep_apart(x: float, y: float, others: list[tuple[float, float, float]],
               table: tuple[float, float, float, float]) -> tuple[float, float]:
    """Position (x, y) moved out of every other character's disc (ox, oy, least distance),
    along the line between the centres (a puck pushed aside, as two pucks cannot overlap), as
    far as the table's edge lets it (:func:`table_reach`), then kept on the table. Discs are
    visited in order; a position pinned between two is pushed from each in turn.

    Pushed the whole way and clamped, a point beyond the edge went back along the edge toward
    the corner: a hand resting 7 cm from the afraid character (personal space 0.105 m) in a
    corner held it there for good, as every step out along an edge came back to the corner
    (bench/fidelity.py's pursuit, seed 0: 13.4 s of 40 at (0, 0), contact 0.30; a hand that
    stays on it, tests/puppet_master/test_pm_personal_space.py: contact 0.33-0.42). Measured
    with bench/fidelity.py, thresholds met on the open paths / pursuit (time at an edge under
    pursuit, mean): --seeds 0,1,2,3,4,5 659 -> 659 / 37 -> 41 (0.565 -> 0.533), --seeds 7
    107 -> 109 / 8 -> 8 (0.48 -> 0.48; the afraid character's misses 7 -> 5), --seeds
    8,9,10,11,12,13 651 -> 651 / 42 -> 38 (0.458 -> 0.500); the open paths of seeds 0-5 and
    8-13 are the same to the last digit. It frees the cornered character; it does not keep it
    off the edges (see :func:`keep_on_table`).

    Two or more discs are visited again while a pass pushed the position (at most
    ``APART_PASSES`` passes): in one pass, three reactors of one main left one pushed out of
    the second disc into the first. A position on a disc's centre goes out along the first of
    +x, -x, +y, -y with room for the whole push (:func:`_free_axis`); it went a whole metre
    along +x before (d taken as 1 m: of two reactors of one behaviour, which start on one spot,
    the second began at the table's edge, and a third on top of it). Shipped characters, 3-5
    on one main (lovers, bullies, stalkers, afraid, friends, mixed, sizes 0.04-0.25 m, a main
    at 0.5-1 m/s; 22 scenes of 30 s at 60 Hz), least gap over the pair's mean size on any
    frame: 0.0 before; 4 / 16 passes 0.904 / 0.921 (on the three worst scenes 0.904-0.913 /
    0.961-0.975; 64 passes 0.929-0.975). One disc (a main's personal space) is one pass, as
    it was, so a reactor alone moves as before to the last digit.

    On a later pass a position that the edge holds more than ``SLIDE_DEPTH`` of the least
    distance inside a disc (the line from the centre runs into the edge) slides along that
    edge (:func:`along_edge`): reactors chasing each other in a ring (bully -> afraid ->
    stalker -> bully or a puck, 12 runs of 30 s) were pinned in corners, least gap over their
    size 0.446-0.918 on 6 runs, 38 frames under 0.9; with the slide 0.954-1.0, none. Sliding
    out of any overlap (depth 0) made it jump: frames stepping more than the character's
    largest demonstrated step 4 -> 10 (1.71 -> 2.51 x; a stalker 0.4 mm inside slid 1.8 cm);
    at 0.05: 3 (1.71 x). The 22 scenes above: least 0.921 -> 0.948. Sliding on the first pass
    too (one disc: a character its main presses into an edge; out_of_way's scenes, 36 per
    character: share inside the main's disc 0.0201 -> 0.0149, least over it 0.024 -> 0.081,
    bench/fidelity.py --seeds 0-5 the same to the last digit) held the afraid character herded
    by a hand that stays on it along the edge (tests/puppet_master/test_pm_personal_space.py,
    contact / at an edge from (0.9, 0.5) 0.001 / 0.63 -> 0.000 / 0.78; at a depth of 0.25 0.023
    / 0.76): not used."""
    for visit in range(APART_PASSES):
        moved = False
        for ox, oy, least in others:
            dx, dy = x - ox, y - oy
            d = math.hypot(dx, dy)
            if d < least:
                if d < 1e-9:
                    dx, dy = _free_axis(ox, oy, least, table)
                    push, d = min(least, table_reach(ox, oy, dx, dy, table)), 1.0
                else:
                    push = max(d, min(least, table_reach(ox, oy, dx / d, dy / d, table)))
                x, y = ox + dx * push / d, oy + dy * push / d
                if visit > 0 and push < (1.0 - SLIDE_DEPTH) * least:     # pinned at an edge
                    x, y = along_edge(x, y, ox, oy, least, table)
                moved = True
        if not moved or len(others) < 2:
            break
    return clamp_to_table(x, y, table)


APART_PASSES = 16    # passes over two or more discs (keep_apart)


def along_edge(x: float, y: float, ox: float, oy: float, least: float,
               table: tuple[float, float, float, float]) -> tuple[float, float]:
    """(x, y) on a table edge moved along that edge to ``least`` metres from (ox, oy), away
    from it (a puck pushed against a wall slides along it), where that point is on the table;
    else (x, y)."""
    x0, y0, x1, y1 = table
    if x <= x0 + EDGE_EPS or x >= x1 - EDGE_EPS:          # a side edge: along y
        ny = _along(x - ox, oy, y, y0, y1, least)
        if ny == ny:
            return x, ny
    if y <= y0 + EDGE_EPS or y >= y1 - EDGE_EPS:          # the bottom or top edge: along x
        nx = _along(y - oy, ox, x, x0, x1, least)
        if nx == nx:
            return nx, y
    return x, y


def _along(off: float, centre: float, at: float, lo: float, hi: float, least: float) -> float:
    """Where along an edge (from ``at``, away from the disc's ``centre`` coordinate) a disc
    whose centre lies ``off`` metres across from the edge is ``least`` away; nan where no such
    point lies within [lo, hi]."""
    h = least * least - off * off
    if h > 0.0:
        n = centre + math.copysign(math.sqrt(h), at - centre)
        if lo <= n <= hi:
            return n
    return math.nan


EDGE_EPS = 1e-9      # metres: a position this near an edge is on it (along_edge)
SLIDE_DEPTH = 0.05   # share of the least distance a pinned position slides past (keep_apart)


def _free_axis(x: float, y: float, least: float,
               table: tuple[float, float, float, float]) -> tuple[float, float]:
    """The first of the unit directions +x, -x, +y, -y along which (x, y) has ``least``
    metres of table, else the one with the most."""
    best, most = (1.0, 0.0), -math.inf
    for ux, uy in ((1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)):
        reach = table_reach(x, y, ux, uy, table)
        if reach >= least:
            return ux, uy
        if reach > most:
            best, most = (ux, uy), reach
    return best


LEAD = 1.0     # the main's way read ahead: LEAD x the steps a character needs to leave its disc


def out_of_way(x: float, y: float, mx: float, my: float, vx: float, vy: float, least: float,
               largest: float, table: tuple[float, float, float, float]) -> tuple[float, float]:
    """Position (x, y) moved out of the way of a main at (mx, my) stepping (vx, vy) metres per
    step, when it steps farther than the character's ``largest`` step: the way the main takes
    over the next LEAD x least / largest steps (the steps the character needs to leave a disc
    of ``least`` metres at its largest step), widened by ``least``. Pushed from the way's
    nearest point (across the main's line beside it, on ahead beyond its end, to the main's
    left on its line), as far as the table lets it; a position behind the main, or out of its
    way, is kept. A puppeteer's character steps aside as the hand comes at it; given way only
    when run into (keep_apart, the step capped at its largest), a main faster than it was ever
    shown to move ran it over.

    Unseen scenes (a main at 0.3-1.5 m/s run straight at the character, 0.3-0.8 x its disc
    beside it, or herding it into a corner, from 0.35-0.6 m; tables 0.6 x 0.4 - 3.0 x 0.5 m,
    main 30-60 Hz, 24 s; the five shipped characters, 36 scenes each), share of steps nearer
    the main than its disc (Behavior.main_disc) / least distance over the disc, mean over
    scenes: lover 0.1015 / 0.124 -> 0.0548 / 0.366, bully 0.0068 / 0.698 -> 0.0040 / 0.813,
    stalker 0.0167 / 0.382 -> 0.0034 / 0.825, afraid 0.0504 / 0.363 -> 0.0175 / 0.643,
    playful friend 0.0242 / 0.482 -> 0.0209 / 0.553; no step over the largest before or after.
    The visitor at 0.5-1x its pace on a 1.2 x 0.8 m table (60 Hz, 40 s), least distance: afraid
    0.053 -> 0.078 m, stalker 0.035 -> 0.053, lover 0.021 -> 0.069; its first 8 s of seed 27
    the stalker 0.011 -> 0.060 m (the main passed over it), the afraid one 0.077 -> 0.105.
    bench/fidelity.py --seeds 0-5: every figure the same to the last digit (677 of 720, the engine's
    alone 7, pursuit 47); --seeds 40-51 --perturb 2: 1328 (31), pursuit 85 -> 1329 (30), 85 (its
    three runs 1328 / 1339 / 1335 -> 1329 / 1338 / 1336: the lover's, beside the fast reversing
    main, 29 / 26 / 25 -> 28 / 27 / 24 misses). Other reading distances, 12 of those scenes, share
    inside / least over the disc (means over the characters): LEAD 1 0.0178 / 0.628, 1.5 0.0197 /
    0.610, 2 0.0203 / 0.564 (read farther, the way's end lies beyond where the main turns); on the
    36: LEAD 0.75 / 1 / 1.25 0.0207 / 0.0201 / 0.0190, least 0.597 / 0.640 / 0.643, but at 1.25 the
    least of any scene lower for the afraid one (0.203 -> 0.143) and the playful friend (0.057 ->
    0.036), the bully's mean 0.813 -> 0.778. Pushed across to the other side of the main's line
    where its own side's edge cuts the push short and the position lies within 0.5 / 1 x least of
    the line (36 scenes): share inside 0.0201 -> 0.0174 / 0.0172, the least over the disc 0.024 ->
    0.046 / 0.092, but the afraid one's share 0.0175 -> 0.0176 / 0.0177 and the least beside a
    passing main lower (lover 0.35 -> 0.12, stalker 0.54 -> 0.17 / 0.21: it crosses in front of the
    main): not used. A step toward the pushed position is cut to the largest step after it
    (step_detail.py) and can end inside the main's disc where the push was across (a 30 Hz main
    beside the stalker on a 2.0 x 1.2 m table: 0.051 -> 0.040 m); kept only where the step so cut
    ends out of the disc: share inside 0.0201 -> 0.0226 (the afraid one 0.0175 -> 0.0236, least over
    the disc 0.643 -> 0.534); the cut step kept apart and cut again where it so ends: 0.0201 ->
    0.0200, but the bully's, stalker's and afraid one's shares higher (0.0040 / 0.0034 / 0.0175 ->
    0.0043 / 0.0038 / 0.0183): not used."""
    v2 = vx * vx + vy * vy
    ahead = LEAD * least / largest
    if v2 <= largest * largest or ahead <= 0.0:
        return x, y
    ex, ey = vx * ahead, vy * ahead
    u = ((x - mx) * ex + (y - my) * ey) / (v2 * ahead * ahead)
    if u <= 0.0:
        return x, y
    u = min(u, 1.0)
    cx, cy = mx + u * ex, my + u * ey
    dx, dy = x - cx, y - cy
    d = math.hypot(dx, dy)
    if d >= least:
        return x, y
    if d < 1e-9:                         # on the main's line: to its left
        dx, dy, d = -vy, vx, math.sqrt(v2)
    push = max(d, min(least, table_reach(cx, cy, dx / d, dy / d, table)))
    return clamp_to_table(cx + dx * push / d, cy + dy * push / d, table)
