"""General trajectory generation (paper section 4.4.1).

Each step: the training sample after the best match (the target) gives a relative position, a
velocity and a look. The target relative position is carried into the main character's current
frame (or kept at the reactor's world bearing, look.train_place) and onto the table
(:func:`table_boundary.fit_target`). The step repeats the demonstrated step relative to the main
plus a share of the way to the target (engine.Params.relative_motion; where the place is held in
the world, the demonstrated reactor's own way of moving, demonstrated.own_steps, which with the
other measures of the demonstration taken at training is in demonstrated.py), or, with that
share 0 (the paper), heads for the target (:func:`step_around`: around the main, not through it)
with the length of the target velocity (engine.Params.catch_up may lengthen it when far off);
the last three steps are averaged (the paper's linear smooth), the patch's Haar detail turns the
averaged step (detail.py), the table keeps the reactor (:func:`table_boundary.keep_on_table`)
and so do the other characters (:func:`apart.keep_apart`); the look follows look.py at
a limited turn rate (:func:`limit_turn`).

Positions in table metres, steps in metres per generation step, angles in radians.
"""

from __future__ import annotations

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
    720 (bully -5, friend -3, stalker +1; seed 7 110 -> 109): not used. The stalker's correction
    along this path toward nearer targets as well (its loops orbit, demonstrated.own_steps): its
    misses (the engine's) on seeds 0-5, 8-13, 26-31 26 (17) -> 37 (26). Not used.

    The characters with a personal space take the straight correction. Chased (the afraid
    one, seeds 0, 46, 50) it is nearly all across the bearing at places in the main's frame:
    0.31-0.38 m/s sideways, 0.01-0.06 outward, the target 5 cm farther out but 0.37-0.43 rad
    round the main from the live bearing (over 0.5 rad on 24-30% of those steps). This path for
    them too, tuning seeds 0-5, 40-51 (misses, the engine's alone): lover 44 (8) -> 42 (9),
    afraid open 65 (4) -> 69 (3), chased 12 (8) -> 11 (6); chased distance 0.298 -> 0.300 m
    (its designer's 0.40), facing 0.182 -> 0.167 (0.239 shown). Not used."""
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


def less_approach(msx: float, msy: float, bx: float, by: float, shown: float, cx: float,
                  cy: float) -> tuple[float, float]:
    """The drift correction (cx, cy) (metres) of a character that keeps pace with its main
    (the stalker), less its part into the main by as much as the live main's step (msx, msy)
    towards it goes beyond what the matched moment's main stepped towards it (``shown``,
    metres, demonstrated.main_approach; none where it stepped away). (bx, by): the reactor
    from its main (any length); nothing where they are within 1e-9 m.

    Traced on the 18 fast reversing paths of seeds 0-5, 8-13, 26-31 (contact 0.044 mean
    against its designer's 0.039, the band's top 0.042): half of the stalker's steps within
    0.08 m of its main (637 of 1266) replayed the demonstration's three passes into its main
    (matched moments 0.062 m off), which the match took on 4.2% of its steps against their
    2.2% of the demonstration, where the live main walked at it at 0.21 m/s against the
    moment's main's 0.10: on a run-up the copied relative step and this correction (up to the
    moment's pace, 0.5 m/s, toward a moment 0.08-0.1 m nearer than the live one) closed
    the gap at 0.75 m/s where the demonstration closed at 0.53. The stalker alone on those 54
    paths, relative_motion x 1, 1 +- 0.001, 1 +- 0.002 (misses, the engine's alone): 150 (81)
    -> 134 (82); fast contact 0.043-0.046 -> 0.036-0.037 mean, its misses 46 (24) -> 26 (16);
    fast speed 9 -> 6, loops still/moving 17 -> 14, orbit 17 -> 15; but the slow paths'
    still/moving 11 (2) -> 19 (9) (its mean there 0.307 -> 0.291, shown 0.285: which paths
    cross the band moved), loops speed 10 (5) -> 13 (8). bench/fidelity.py --seeds 0-5 /
    8-13 / 26-31: met 674 / 669 / 661 -> 676 / 671 / 661, the engine's alone 8 / 13 / 15 -> 8
    / 13 / 16; the other characters and the pursuit the same to the last digit. Measured too
    (five runs as above unless said): the whole inward part while the main comes at it,
    not only beyond the moment's main's, 147 (93) (slow still/moving 22); that only while the
    main walks (not StepSenses._main_stopped) 144 (93), beyond the moment's 148 (98) (loops
    contact 32); only at moments closing in 153 (100); the smooth's remembered steps losing
    their inward part once the raw step stops closing (three runs, against 90 (50)) 108 (68),
    with the governor's filter 97 (64); one run each against 30 (16): the live closing held
    to the moment's 63-147 (contact gone), the steps since the last touch among its features
    (behavior.py, as the playful friend) 33 (20) (loops contact under the band), the still
    cap (Behavior.still_speed) not holding steps away from the main 37 (23), within 0.08 m 32
    (18), at the 65th / 75th percentile 38 (24) / 32 (19). None of those used.

    The mirror for a character that keeps away (the afraid one, at places held in the world):
    the live main's step towards it beyond the moment's main's added outward, its world cap
    raised by as much, or both. Chased by visitors.Pursuer it keeps 0.298 m from its visitor
    (tuning seeds 0-5, 40-51; its designer 0.40, shown 0.37), 8-10 cm nearer than its designer
    whatever the visitor does (chasing 0.255 / 0.333 m, pausing 0.319 / 0.411, pulling back
    0.435 / 0.541, wandering 0.377 / 0.483; seeds 0-5, 40-45), so it faces the visitor less
    (0.182 against 0.239 shown: nearer, the match takes fleeing moments, which look away).
    Afraid alone, open met of 144 / 288 and chased of 48 / 96 on seeds 0-5 / 40-51, against
    123 / 244, 47 / 85: both 119 / 248, 45 / 84; the cap 114 / 254, 45 / 83; the step 116 /
    242, 44 / 89; chased distance 0.288-0.293 m. Its Params on those 18 chases (distance,
    facing, misses of 144; 0.298, 0.182, 12): half_life 4 / 10 0.286 / 0.291, 0.156 / 0.166,
    14 / 12; w_rel_look 0 0.269, 0.168, 10; w_rel_position 0.5 / 2 0.289 / 0.288, 13 / 10;
    w_velocity 2 0.279, 10; ratio 0.5 / 2 0.293 / 0.290, 9 / 9; relative_motion 0.2 0.296,
    20. The place in the main's frame taken at the moment's distance on the live bearing
    outside charges (no sideways correction): open 316, chased 135, distance 0.298. Nothing
    kept: the distance holds at 0.27-0.31 m whatever the step or the match."""
    r = math.hypot(bx, by)
    if r <= 1e-9:
        return cx, cy
    ex, ey = bx / r, by / r
    beyond = msx * ex + msy * ey - max(shown, 0.0)
    inward = -(cx * ex + cy * ey)
    if beyond > 0.0 and inward > 0.0:
        cut = min(inward, beyond)
        cx, cy = cx + cut * ex, cy + cut * ey
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


def turn_between(ax: float, ay: float, bx: float, by: float) -> tuple[float, float]:
    """Cosine and sine of the turn from the bearing (ax, ay) to the bearing (bx, by) (the
    reactor from its main, metres); no turn (1, 0) where either is within 1e-9 m."""
    la, lb = math.hypot(ax, ay), math.hypot(bx, by)
    if la < 1e-9 or lb < 1e-9:
        return 1.0, 0.0
    n = la * lb
    return (ax * bx + ay * by) / n, (ax * by - ay * bx) / n


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
    (lover) and 27 (afraid): the lover, its tremor not holding it back, outruns fast mains; its
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

    def restart(self, sx: float, sy: float) -> None:
        """Every remembered raw step set to (sx, sy): the next mean starts from that step."""
        self.xs[:] = [sx] * self.size
        self.ys[:] = [sy] * self.size

    def turn(self, c: float, s: float) -> None:
        """Every remembered raw step turned by the angle whose cosine and sine are (c, s).

        A character that circles its main (Behavior.circling: the playful friend, 2.4 rad/s
        round it) has its remembered steps turned by its bearing's turn from the main before
        each mean (step.py, the compiled step alike): averaged as taken, the earlier ones
        point out of the circle (a lag of about one step's turn), so the smooth drove it
        outward and the drift correction held it 0.9 cm beyond its matched moments' distance
        (seeds 0-2, every path; 0.4 cm now, tests/puppet_master/test_pm_circling.py); its
        darts, begun farther out, touched its main less: contact 0.032 -> 0.038 mean over the
        54 paths of seeds 0-5, 8-13, 26-31 (0.041 shown), orbit 2.12 -> 2.15 rad/s (2.30).
        bench/fidelity.py on those seeds: met 670 / 666 / 661 -> 668 / 667 / 665 of 720, the
        engine's alone 7 / 16 / 21 -> 9 / 15 / 17 (the friend's 1 / 6 / 4 -> 3 / 5 / 0, all
        contact), the other characters and the pursuit the same to the last digit; the friend
        alone with the drift share x 1, 1 +- 0.001, 1 +- 0.002: 11, 10, 13, 10, 15 -> 8, 8,
        10, 14, 13 misses. Measured too (its misses over the first three of those runs, 34
        before): the texture governor's filter turned as well 35; the steps since its last
        dart nearer than 0.12 m as a feature (features.since_push) at weight 0.5 33, 1.0 32;
        at a world place the correction's part along the bearing added after the cap 50
        (contact 0.028: it pulls out as well), its inward part only 42, only at moments going
        inward 43; the world cap raised by the main's carried step 64 (orbit 2.29, contact
        0.026). None is used. The turn for every character (one run, the misses and the
        engine's alone on those 54 paths): the lover 36 (5) -> 38 (7), the stalker 31 (18) ->
        33 (20), the bully 10 (5) -> 9 (5), the afraid one 75 (5) -> 70 (3); not used."""
        for q in range(self.size):
            x, y = self.xs[q], self.ys[q]
            self.xs[q], self.ys[q] = c * x - s * y, s * x + c * y

    def lose_inward(self, bx: float, by: float) -> None:
        """Every remembered raw step loses its part against the bearing (bx, by) (the reactor
        from its main, metres, any length), as a puck pushed aside by its main's keeps none
        of its motion into it; nothing where the bearing is within 1e-9 m.

        The stalker (Behavior.keeps_pace) ran through its main at reversals: the place 0.35 m
        behind a main that turns back lies on its far side, and the drift correction took
        the straight line (1-3 cm between centres: of its 170-178 episodes within 0.08 m on
        the 54 paths of seeds 0-5, 8-13, 26-31, 62-69 came nearer than 0.04 m). Its
        designer's puck is pushed aside at 0.055 m and loses the part of its velocity into
        the main (designers.demonstrate); its demonstration never comes nearer than 0.053 m.
        Kept out of the main's disc at that least distance (Behavior.main_disc) and with this
        loss, none comes nearer than the disc (tests/puppet_master/test_pm_stalker_apart.py).
        The stalker alone on those paths, misses (the engine's alone) with the drift share x
        1, 1 + 0.001, 1 - 0.001, 1 + 0.002, 1 - 0.002: before 31 (18), 32 (19), 30 (17), 30
        (18), 29 (17), sum 152 (89); now 30 (16), 29 (15), 31 (16), 29 (16), 31 (18), sum 150
        (81); with 1 + 0.003, 1 - 0.003, 1 + 0.004, 1 - 0.004 as well: before 29 (17), 34
        (22), 34 (21), 31 (19), now 31 (17), 39 (24), 34 (21), 31 (19); over the nine runs 280
        (168) -> 285 (162): the misses as before within the runs' spread, the passes through
        the main gone. Fast-path contact 0.042-0.045 -> 0.043-0.048 over the nine runs (its
        designer 0.039, at most 0.042): held against the disc a little longer. The disc
        alone 35, 34, 32, 32, 30, sum 163 (89): still/moving missed 40 times over the five
        runs (now 29, before 33); with the governor's filter losing its inward part as well
        (disc 0.053 m) 152 (83). bench/fidelity.py --seeds 0,1,2,3,4,5 / 8,...,13 /
        26,...,31: met 668 / 667 / 665 -> 669 / 665 / 667 of 720, the engine's alone 9 / 15 /
        17 -> 8 / 16 / 15 (the stalker's misses 8 (3) / 10 (6) / 13 (9) -> 7 (2) / 12 (7) /
        11 (7)), the other characters and the pursuit the same to the last digit.

        Its fast-path contact (0.044 mean, limit 0.042) traced on the 18 fast paths of those
        seeds: 109 episodes within 0.08 m against its designer's 110, alike on the way in
        (3.8 / 3.6 samples to the least distance) but at the disc (under 0.056 m) 4.7
        samples an episode against 3.8, pushed along by a main coming at it 3.1 against 2.3.
        Seed 30 fast (0.071, its designer 0.037): shoved 8-12 samples at places in the main's
        frame whose demonstrated main walked past the stalker on its other side (0.085 m on
        the left), the relative step copied where the live main walks straight at it. The
        stalker alone, five runs as above, against 150 (81): while pushed, the relative step
        turned by the live bearing's difference from the moment's 156 (81) (fast contact
        0.044 -> 0.043, shoved 2.6 samples, orbit misses 18 -> 24, all low), BestMatch
        taking the situation's match while pushed 153 (84) (shoved 3.3); one run each
        against 30 (16): the step's part into the main dropped while pushed 35 (19), the
        correction at the top speed while pushed 31 (18) (shoved 3.4); the disc at 0.054 /
        0.055 m (its designer's contact, the least shown being lowered by the tremor) 34 (18)
        / 32 (18). Its drift correction at the top speed instead of the moment's pace where
        it is nearer its main than the moment (backing off after a pass, as its designer)
        181 (100) (fast contact 0.040, speed misses 4 -> 10-11); only within 0.08 m 154 (85)
        (0.043); that with the turned step 159 (90) (0.042): the fast paths' contact spreads
        over 0.004-0.071 either way, and a mean 0.002 lower moves misses from the high side
        to the low. None used. Its designer on the unseen mains without the camera's jitter
        (as the hand that made the demonstration perceived its main) touches less: fast
        contact 0.033 against 0.039 (met on 14 / 10 of 18)."""
        length = math.hypot(bx, by)
        if length <= 1e-9:
            return
        ux, uy = bx / length, by / length
        for q in range(self.size):
            inward = self.xs[q] * ux + self.ys[q] * uy
            if inward < 0.0:
                self.xs[q] -= inward * ux
                self.ys[q] -= inward * uy

    def push(self, sx: float, sy: float) -> tuple[float, float]:
        """Add a raw step; returns the mean of the last ``size`` steps."""
        self.xs[self.i] = sx
        self.ys[self.i] = sy
        self.i = (self.i + 1) % self.size
        return sum(self.xs) / self.size, sum(self.ys) / self.size


def limit_turn(previous: float, desired: float, max_delta: float) -> float:
    """Direction turned from ``previous`` toward ``desired`` by at most ``max_delta`` radians."""
    d = wrap_angle(desired - previous)
    d = min(max(d, -max_delta), max_delta)
    return wrap_angle(previous + d)
