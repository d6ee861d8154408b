"""Where a generation step may end among the characters: out of the other characters' discs
(:func:`keep_apart`, sliding along an edge that holds it in one, :func:`along_edge`) and out of
the way a fast main is about to take (:func:`out_of_way`). Positions in table metres, tables as
(x0, y0, x1, y1); the table's own edges: :mod:`table_boundary`.
"""

from __future__ import annotations

import math

from behaviors.puppet_master.table_boundary import clamp_to_table, table_reach


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
    / 0.76): not used; the main's own disc slides a position only where the main steps into
    the edge (:func:`pressed_along_edge`)."""
    for visit in range(APART_PASSES):
        moved = False
        for ox, oy, least in others:
            dx, dy = x - ox, y - oy
            d = math.hypot(dx, dy)
            if d < least:
                if d < 1e-9:
                    dx, dy = _free_axis(ox, oy, least, table, others)
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


def _free_axis(x: float, y: float, least: float, table: tuple[float, float, float, float],
               others: list[tuple[float, float, float]]) -> tuple[float, float]:
    """The first of the unit directions +x, -x, +y, -y along which (x, y) has ``least``
    metres of table and ends out of every disc of ``others``, else the first with that room,
    else the one with the most. Three reactors of one main start on one spot: in a corner the
    third went from the first's disc onto the second and back on every pass (3.0 x 0.5 m table,
    two of 36 scenes, every character: gap 0 for the first two frames)."""
    best, most, roomy = (1.0, 0.0), -math.inf, (math.nan, 0.0)
    for ux, uy in ((1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)):
        reach = table_reach(x, y, ux, uy, table)
        if reach >= least:
            px, py = x + ux * least, y + uy * least
            if all(math.hypot(px - ox, py - oy) >= d - 1e-9 for ox, oy, d in others):
                return ux, uy
            if roomy[0] != roomy[0]:
                roomy = (ux, uy)
        if reach > most:
            best, most = (ux, uy), reach
    return roomy if roomy[0] == roomy[0] else best


def no_deeper(rx: float, ry: float, x: float, y: float,
              others: list[tuple[float, float, float]],
              table: tuple[float, float, float, float]) -> tuple[float, float]:
    """(x, y), the end of a step from (rx, ry), moved out along the line from each other
    character's centre (ox, oy, least distance) to no deeper in its disc than (rx, ry) was
    (at most ``least``): a step goes round another's body, never into or through it. Where
    the table's edge cuts that push short, the end slides along the edge to that depth
    (:func:`along_edge`).

    keep_apart moves a step's end out of every disc wherever it lands; where the main's disc
    and an edge held the near side, the end went to the far side of a body, and the step, cut
    to the largest, walked through it (a lover along the bottom edge of 0.6 x 0.4 m, 7 steps
    deep in another's body). Three reactors of one main (0.08 m bodies, each kept apart from
    the others' latest shown poses; unseen closed-loop scenes, 0.6 x 0.4 to 3.0 x 0.5 m,
    30-60 Hz, five characters x 36 seeds), seeds 84-119, with the shown pose as it was: least
    gap over the size 0.138 -> 0.934, the largest one-frame shown move over the largest
    step's pace 10.4 -> 1.86 (with the shown pose moved at that pace, engine.Reactor._slid:
    0.949, 1.0). Its cost, with _slid, share of frames inside the main's disc, two / three,
    seeds 12-47, 48-83, 84-119: 0.0613 / 0.0584, 0.0634 / 0.0581, 0.0633 / 0.0595 -> 0.0636 /
    0.0589, 0.0632 / 0.0575, 0.0641 / 0.0600 (a character no longer passes through another
    to leave its main). One character alone sees no body: unchanged."""
    for visit in range(APART_PASSES):
        moved = False
        for ox, oy, least in others:
            dx, dy = x - ox, y - oy
            d = math.hypot(dx, dy)
            keep = min(least, math.hypot(rx - ox, ry - oy))
            if d >= keep:
                continue
            if d < 1e-9:
                x, y = rx, ry
            else:
                x, y = ox + dx * keep / d, oy + dy * keep / d
                cx, cy = clamp_to_table(x, y, table)
                if cx != x or cy != y:
                    x, y = along_edge(cx, cy, ox, oy, keep, table)
            moved = True
        if not moved or len(others) < 2:
            break
    return clamp_to_table(x, y, table)


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
    0.0043 / 0.0038 / 0.0183): not used. A main no faster than the character's largest step
    that presses it into an edge: :func:`pressed_along_edge`."""
    v2 = vx * vx + vy * vy
    ahead = LEAD * least / largest
    if v2 <= largest * largest or ahead <= 0.0:
        return pressed_along_edge(x, y, mx, my, vx, vy, least, table)
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


def pressed_along_edge(x: float, y: float, mx: float, my: float, vx: float, vy: float,
                       least: float, table: tuple[float, float, float, float]
                       ) -> tuple[float, float]:
    """(x, y) inside the disc of ``least`` metres round a main at (mx, my) that closes in on
    it and steps (vx, vy) metres per step into the table's edge that holds it there (the line
    from the main's centre runs into that edge more than SLIDE_DEPTH x ``least`` inside the
    disc), moved along that edge out of the disc (:func:`along_edge`, away from the main);
    else (x, y). A puck pressed against a wall slides along it; a main that stands, moves
    away or runs along the edge without pressing into it leaves the push as keep_apart makes it.

    :func:`out_of_way`'s unseen scenes (36 per character), share of steps inside the main's
    disc / least distance over it, mean over scenes (least of any): seeds 12-47 0.0201 / 0.640
    (0.024) -> 0.0183 / 0.671 (0.024), lover 0.0548 -> 0.0532, bully 0.0040 -> 0.0020, stalker
    0.0034 -> 0.0034, afraid 0.0175 -> 0.0158, playful friend 0.0209 -> 0.0169, every
    character's least of any scene the same or farther; seeds 48-83 0.0191 / 0.607 (0.059) ->
    0.0176 / 0.639 (0.062), lover 0.0435 -> 0.0426, bully 0.0046 -> 0.0032, afraid 0.0190 ->
    0.0174, playful friend 0.0245 -> 0.0208, but the stalker 0.0039 -> 0.0042 (one scene: the
    main walking along the top edge pressed into it slid it ahead into a corner); seeds 84-119
    0.0212 -> 0.0189, lover 0.0609 -> 0.0498, bully 0.0044 -> 0.0031, playful friend 0.0180 ->
    0.0179, but the afraid one 0.0177 -> 0.0180 and the stalker 0.0050 -> 0.0057 (one scene, a
    main walking along the edge over it where this does not fire). No step over the largest.
    bench/fidelity.py --seeds 0-5 and --seeds 40-51 --perturb 2: every figure the same (677 of
    720, pursuit 47; 1329, pursuit 85). tests/puppet_master/test_pm_personal_space.py's herded
    afraid character (contact / at an edge) from (0.3, 0.3) 0.0725 / 0.80 -> 0.010 / 0.36,
    from (0.9, 0.5) 0.0013 / 0.63 unchanged; that herder from 14 starts at 0.25 / 0.35 / 0.45
    m/s: contact 0.0235 -> 0.0118, inside the disc 0.050 -> 0.029, at an edge 0.703 -> 0.706;
    the shipped lover so herded 0.0671 -> 0.0594, 0.066 -> 0.058, 0.777 -> 0.732.
    Gated only on the main closing in (as keep_apart's slide on its first pass): 0.0178 on
    seeds 12-47, the 42 herds' contact 0.0054, at an edge 0.702, but from (0.9, 0.5) at an edge
    0.63 -> 0.78 (the herds' edge share per start spreads 0.36-1.0 either way); closing in at
    0.2 / 0.25 / 0.3 / 0.35 x the character's largest step instead: 0.0181 / 0.0191 / 0.0188 /
    0.0189, the afraid one's 0.0177 / 0.0191 / 0.0192 / 0.0182; into the edge at 0.1 x the
    largest step: 0.0191 (the lover's least on seeds 48-83 0.079 -> 0.020), at a quarter of
    the main's step: 0.0185, the lover's 0.0435 -> 0.0443 on seeds 48-83; more into the edge
    than along the slide: 0.0185 / 0.0188; only where the main does not step the slide's way:
    0.0180 / 0.0190; not into a corner ahead of the main: lover 0.0552, stalker 0.0045 on seeds
    48-83. Slid ahead of the main's own way along the edge / behind it: 0.0184 / 0.0166, but
    the herded one in contact 0.44 of the time from (0.9, 0.5) behind it (the capped step
    crosses the main's disc); to the disc's edge beside the main's way: contact 0.14 (42
    herds). Not used."""
    dx, dy = x - mx, y - my
    d = math.hypot(dx, dy)
    if d >= least or d < 1e-9 or dx * vx + dy * vy < 0.0:
        return x, y
    push = max(d, min(least, table_reach(mx, my, dx / d, dy / d, table)))
    if push >= (1.0 - SLIDE_DEPTH) * least:
        return x, y
    px, py = clamp_to_table(mx + dx * push / d, my + dy * push / d, table)
    x0, y0, x1, y1 = table
    into = 0.0                           # the main's step into the edge that holds (px, py)
    if px <= x0 + EDGE_EPS:
        into = -vx
    elif px >= x1 - EDGE_EPS:
        into = vx
    if py <= y0 + EDGE_EPS:
        into = max(into, -vy)
    elif py >= y1 - EDGE_EPS:
        into = max(into, vy)
    if into <= 0.0:
        return x, y
    return along_edge(px, py, mx, my, least, table)
