"""General trajectory generation (paper section 4.4.1) and the table boundary.

Each step: the training sample after the best match (the target) gives a relative position, a
velocity and a look. The target relative position is carried into the main character's
current frame (or kept at the reactor's world bearing, look.train_place) and onto the table
(:func:`fit_target`). The step repeats the demonstrated step relative to the main plus a share
of the way to the target (engine.Params.relative_motion; where the place is held in the world,
the demonstrated reactor's own way of moving, demonstrated.own_steps, which with the other
measures of the demonstration taken at training is in demonstrated.py), or, with that share 0
(the paper), heads for the target (:func:`step_around`: around the main, not through it) with
the length of the target velocity (engine.Params.catch_up may lengthen it when far off); the
last three steps are averaged (the paper's linear smooth), the patch's Haar detail turns the
averaged step (detail.py), the table keeps the reactor (:func:`keep_on_table`) and so do the
other characters (:func:`keep_apart`); the look follows look.py at a limited turn rate
(:func:`limit_turn`).

Positions in table metres, steps in metres per generation step, angles in radians.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

from tabletop.frames import wrap_angle


def target_position(mx: float, my: float, md: float, fwd: float,
                    left: float) -> tuple[float, float]:
    """World position of a point ``fwd`` ahead and ``left`` to the left of a pose."""
    c, s = math.cos(md), math.sin(md)
    return mx + c * fwd - s * left, my + s * fwd + c * left


def step_toward(rx: float, ry: float, tx: float, ty: float,
                length: float) -> tuple[float, float]:
    """Step of ``length`` metres from (rx, ry) toward (tx, ty); zero when already there."""
    dx, dy = tx - rx, ty - ry
    dist = math.hypot(dx, dy)
    if dist < 1e-12:
        return 0.0, 0.0
    return dx * length / dist, dy * length / dist


def step_around(mx: float, my: float, rx: float, ry: float, tx: float, ty: float,
                length: float) -> tuple[float, float]:
    """Step of ``length`` metres from the reactor (rx, ry) toward the target (tx, ty) along the
    path that is straight in the main's polar frame (distance and bearing from (mx, my) change
    linearly), instead of the straight world line.

    The target is a relative position, so the way to it is relative too: when the target lies
    on the far side of the main (the main reversed, or a circling reactor's next position), the
    straight line runs through the main, which no demonstrated keep-away or circling character
    ever does; the polar path goes around at the demonstrated distances. With no bearing change
    it is the straight line. A target nearer than ``length`` is reached, not overshot: the
    paper scales the step to the target velocity, which near a resting target makes the
    character dither across it every step (measured: direction jitter of 0.4-0.9 rad RMS on a
    smooth follower); stopping there keeps a smooth demonstration smooth.
    """
    ax, ay = rx - mx, ry - my
    bx, by = tx - mx, ty - my
    ra, rb = math.hypot(ax, ay), math.hypot(bx, by)
    if ra < 1e-6 or rb < 1e-6:
        return step_toward(rx, ry, tx, ty, min(length, math.hypot(tx - rx, ty - ry)))
    a0 = math.atan2(ay, ax)
    da = math.remainder(math.atan2(by, bx) - a0, math.tau)
    path = math.hypot(rb - ra, 0.5 * (ra + rb) * da)
    if path <= length or path < 1e-12:
        return tx - rx, ty - ry
    f = length / path
    rho, ang = ra + f * (rb - ra), a0 + f * da
    return step_toward(rx, ry, mx + rho * math.cos(ang), my + rho * math.sin(ang), length)


def share_around(mx: float, my: float, rx: float, ry: float, tx: float, ty: float,
                 share: float) -> tuple[float, float]:
    """Step (metres) covering ``share`` (0..1) of the way from the reactor (rx, ry) to a target
    (tx, ty) farther from the main at (mx, my) than the reactor is, along :func:`step_around`'s
    path (distance and bearing from the main changing linearly); a target at most as far
    from the main (or either on it) is taken along the straight line.

    A relative target is a place round the main: on the straight line to one farther out at
    another bearing the reactor first closes in on the main. The playful friend's drift
    correction so drove it into its main at 0.35-0.75 m/s while the target it corrected toward
    was farther out (0.14 m against a live 0.07-0.13 m), on the fast path.

    What it costs, the friend's contact on seed 0's slow path and loops (0.019 / 0.020 against
    0.041): its darts stop short (median least distance of a dip 0.097 / 0.102 m against
    0.077 demonstrated), where the matched moments dart deeper (under 0.08 m in 38% of the
    dips; 78% with the straight correction). Traced (seed 0 slow): the demonstrated step
    relative to the main is carried in the main's frame, and the live friend circles at
    another bearing than the matched moment, up to the far side, so a dart's inward step
    comes out sideways or outward (0.27-0.47 m/s outward while the moment darted in) and the
    correction alone pulls it in. That step turned by the bearing between the live reactor
    and the moment (characters without a personal space, outside charges) meets both paths'
    contact (0.049 / 0.022) but bench/fidelity.py --seeds 0,1,2,3,4,5 falls 635 -> 628 of
    720 (bully -5, friend -3, stalker +1; seed 7 110 -> 109): not used."""
    cx, cy = share * (tx - rx), share * (ty - ry)
    ax, ay = rx - mx, ry - my
    bx, by = tx - mx, ty - my
    ra, rb = math.hypot(ax, ay), math.hypot(bx, by)
    if ra > 1e-6 and rb > 1e-6 and rb > ra:
        a0 = math.atan2(ay, ax)
        da = math.remainder(math.atan2(by, bx) - a0, math.tau)
        rho, ang = ra + share * (rb - ra), a0 + share * da
        cx, cy = mx + rho * math.cos(ang) - rx, my + rho * math.sin(ang) - ry
    return cx, cy


def capped(sx: float, sy: float, cap: float) -> tuple[float, float]:
    """Step (sx, sy) (metres) shortened to at most ``cap`` metres, its direction kept."""
    length = math.hypot(sx, sy)
    if length > cap:
        return sx * cap / length, sy * cap / length
    return sx, sy


def kept_straightness(sx: float, sy: float, xs: Sequence[float], ys: Sequence[float],
                      share: float, kept: float, decay: float,
                      most: float) -> tuple[float, float, float]:
    """The smoothed step (sx, sy) (metres) of the raw steps ``xs``, ``ys`` it averages, and
    ``kept``, the running share of the raw steps' mean length the smooth has kept (its
    exponential mean, ``decay`` per step): where that share has fallen below ``share`` (the
    demonstration's, Behavior.straightness) the step is lengthened by their ratio, at most to
    ``most`` metres, never shortened. Returns the step and the updated running share."""
    n = len(xs)
    total = 0.0
    for q in range(n):
        total += math.hypot(xs[q], ys[q])
    mean = total / n
    length = math.hypot(sx, sy)
    if mean <= 1e-12:
        return sx, sy, kept
    kept += decay * (length / mean - kept)
    if kept >= share or length <= 1e-12:
        return sx, sy, kept
    f = min(share / kept, most / length)
    if f <= 1.0:
        return sx, sy, kept
    return sx * f, sy * f, kept


def mean_capped(px: float, py: float, sx: float, sy: float, cap: float,
                size: int) -> tuple[float, float]:
    """Raw step (sx, sy) (metres) held so that the mean of it and the ``size`` - 1 raw steps
    before it (their sum (px, py)), which is what the linear smooth passes on, moves at most
    ``cap`` metres: shortened only as far as that mean needs, never below ``cap`` (where it
    is longer than ``cap``) and never longer than it was.

    A cap on every raw step (step.py) leaves what the steps' change of direction takes: the
    lover beside its walking main (seed 3 slow) has raw steps of 0.128 m/s whose mean over
    three moves 0.109; capped one by one at the matched moment's speed (0.103) they are 0.093
    m/s, their mean over three 0.079, and it walks at 0.073 m/s (its designer 0.096). A raw
    step longer than ``cap`` can leave the next means beyond reach where the cap falls (a
    fast moment's 0.0095 m, then 0.0082: mean 0.0112 m, over the lover's demonstrated
    largest step, 0.0098); the step therefore caps the smoothed step too (step.py)."""
    length = math.hypot(sx, sy)
    if length <= cap:
        return sx, sy
    f = cap / length
    most = size * cap
    c = px * px + py * py - most * most
    if c < 0.0 and size > 1:     # the earlier steps' sum within reach: up to the rim
        a = sx * sx + sy * sy
        b = px * sx + py * sy
        f = max(f, min((-b + math.sqrt(b * b - a * c)) / a, 1.0))
    return sx * f, sy * f


def rotate_step(sx: float, sy: float, angle: float) -> tuple[float, float]:
    """Turn a step by ``angle`` radians, keeping its length."""
    c, s = math.cos(angle), math.sin(angle)
    return c * sx - s * sy, s * sx + c * sy


class StepSmoother:
    """Linear smooth: the mean of the last ``size`` raw steps (3 in the paper); the history
    starts at rest (zero steps), so a start accelerates gently.

    The mean of vectors shortens a zig-zag: the lover moving beside its slow unseen main
    (seed 2) comes out at 0.087 m/s from raw steps of 0.098 m/s (its matches travelled 0.100 m/s).
    Lengthening the mean back toward the raw steps' mean length, at most to the demonstrated
    travel per step at the match, moved bench/fidelity.py on seeds 0-5 from 601 to 606 of 720
    thresholds (306 -> 301 on seeds 0-2), inside the re-matching noise of about 15: the lover
    gained 4 (slow-path speed W1 0.027-0.040 -> 0.022-0.032 on seeds 1-5, against 0.022) and
    the afraid character 9, the stalker lost 6 (its still-main and fast-path speeds) and the
    bully 4, so it is not used.

    Where the place is held in the world the raw step is capped at the matched moment's speed
    before this smooth (step.py). What the stages leave of the speed, traced with the Python
    step (the fidelity figure's speed over 0.1 s): the afraid character beside its still main
    (seed 5 slow path) matches moments at 0.24 m/s, its composed step is 0.31 (the drift
    correction, 0.25, as long as its own flight, 0.26: the matched moment changes on about half
    of the steps, and with it the place corrected toward), capped 0.20, the two pulling against
    each other leave 0.13 over 0.1 s and this smooth and the detail 0.10 (0.22 demonstrated,
    where beside a still main it fled at 0.39 m/s nearer than 0.3 m, 0.26 at 0.3-0.45 m and 0.11
    farther; on these paths it is at 0.4-0.56 m); beside its walking main 0.45 -> 0.26 -> 0.22
    -> 0.19 (0.25), hence still/moving 0.53 against 0.87. The lover beside its walking main
    (seed 3 slow): 0.128 -> 0.093 (capped on 59% of the steps) -> 0.074 -> 0.073 m/s. The cap
    applied to the smoothed step instead (the raw steps uncapped), measured with
    bench/fidelity.py (seeds 0-5 / 7 / 8-13, against 659 / 107 / 651 of 720 / 120 / 720; pursuit
    37 / 8 / 42 of 48 / 8 / 48): outside charges 656 / 112 / 645, engine-only misses 24 -> 19 on
    seeds 0-5, pursuit 43 / 6 / 39; over the 39 paths of those 13 seeds still/moving met on 33
    instead of 29 (lover) and 28 instead of 24 (afraid), but speed W1 on 22 instead of 26
    (lover) and 27 (afraid): the lover, no longer held by its tremor, outruns fast mains; its
    seed 3 slow path stays at 0.073 m/s: there its slow walk is the composition's, not the
    cap's. In charges too 648 (bully misses 4 -> 15); only where the moment went along with its
    main (k >= FOLLOW_SHARE) 640; only while the live main walks 651; only while it stands 639;
    only where the correction is at most the cap 653 (at most half of it 645); the correction
    given what the own step leaves of the cap, raw 638 (own step capped too 621); the cap from
    the moment's 0.2 s step length (demonstrated.relative_world_steps) after the smooth 632,
    before it 637; the cap after the smooth times that length over the moment's per-sample step
    (its tremor-free share) 613, seeds 8-13 621 (the afraid 22 -> 56 misses); the raw step
    scaled to the moment's speed (the paper's "scaled to the target velocity") 637. None is
    used.

    Measured again with the charges entered in their run-up and the circling friend's place
    held in the world (seeds 0-5: 666 of 720, the engine's alone 18): the cap after this
    smooth (world places, outside charges) 650 / 23, held-out seeds 8-13 638 / 36 against
    652 / 30 (a step perturbed by nothing but 0.1% of its correction share: 655-658 and
    648-651, bench/fidelity.py). On seeds 0-5 the lover gains (misses 16 -> 12, its own 6 -> 3; on
    8-13 15 -> 16; its fast paths' speed W1 is missed with either cap, and by its designer), the
    bully loses (4 -> 12: contact, orbit), the playful friend's darts reach contact half as
    often (1 -> 6 misses; seed 1 slow 0.024 -> 0.011 against 0.026), the afraid 22 -> 30. Not
    a leak of uncapped raw steps into charges and main-frame places: the raw steps held to
    the top speed as well 633. Traced on the lover's slow paths (seeds 0, 3, 5, main walking,
    world places): its composed motion (k x the live main's step + its own step) is as long
    as the matched moments' step (0.106-0.116 against 0.104-0.110 m/s) and as straight (0.79
    of its parts' lengths; 0.72-0.75 demonstrated); on top comes the drift correction
    (0.04-0.11 m/s, a lag of 0.2-2.2 cm behind the matched distance), which the cap takes
    out, and this smooth takes 8-15% of the capped steps (0.093-0.110 -> 0.079-0.101; the
    demonstrated reactor's steps lose 5% over three samples): 0.073-0.097 m/s out, its
    designer 0.096-0.108. Beside its still main (seed 0 slow) 63 of its 229 steps are at
    places held in the main's frame, each entered from a world place with an uncapped
    correction of 0.12 m/s (3 cm): 0.100 m/s there, 0.050 at world places (0.053 shown).
    Measured (seeds 0-5, met / the engine's alone): the cap raised by catch_up x the distance
    to the target 638 / 32 (the lover 16 -> 24 misses), only where k >= FOLLOW_SHARE 631 / 30;
    the smoothed step lengthened to the raw steps' mean length, at most the cap (world
    places outside charges) 643 / 28; the main-frame correction at the moment's pace for the
    characters with a personal space 636 (afraid 22 -> 50), or for 0.25 s after a switch
    from a world place 639 / 27 (the lover's seed 0 slow still speed 0.063 -> 0.040, but it
    walks slower, 0.097 -> 0.091: speed W1 lost); outside charges, a main-frame place's step
    at most the moment's speed plus the way the main's step and turn carry it 638 / 30
    (afraid 22 -> 39, pursuit 41 -> 47). None is used."""

    __slots__ = ("size", "xs", "ys", "i")

    def __init__(self, size: int = 3) -> None:
        self.size = size
        self.xs = [0.0] * size
        self.ys = [0.0] * size
        self.i = 0

    def push(self, sx: float, sy: float) -> tuple[float, float]:
        """Add a raw step; returns the mean of the last ``size`` steps."""
        self.xs[self.i] = sx
        self.ys[self.i] = sy
        self.i = (self.i + 1) % self.size
        return sum(self.xs) / self.size, sum(self.ys) / self.size


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
    7): the table point nearest the target instead 26 / 4; no fitting (keep_on_table slides the step) 28 / 6;
    the correction toward a moved target at most the demonstrated step length there, in a
    place held in the world 39 / 7 (orbit 0.34-0.53), in both place frames 38 / 7; the flight
    kept whole under the cap and the correction given what is left 41 / 7 (orbit 0.38-0.60).
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
    if rho > 1e-9 and x0 <= mx <= x1 and y0 <= my <= y1:
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


def limit_turn(previous: float, desired: float, max_delta: float) -> float:
    """Direction turned from ``previous`` toward ``desired`` by at most ``max_delta`` radians."""
    d = wrap_angle(desired - previous)
    d = min(max(d, -max_delta), max_delta)
    return wrap_angle(previous + d)


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
    off the edges (see :func:`keep_on_table`)."""
    for ox, oy, least in others:
        dx, dy = x - ox, y - oy
        d = math.hypot(dx, dy)
        if d < least:
            if d < 1e-9:
                dx, dy, d = 1.0, 0.0, 1.0
            push = max(d, min(least, table_reach(ox, oy, dx / d, dy / d, table)))
            x, y = ox + dx * push / d, oy + dy * push / d
    return clamp_to_table(x, y, table)
