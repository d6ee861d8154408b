"""The speed profile at a turn: an action whose template slows into a turn is not shown while
its followed state waits there and the input keeps its speed (follower and group alike, beside
the overrun's veto, :mod:`behaviors.mop.overrun`; only what is shown: the rules go on).

The held-out spin wrist's path up to 0.29 of it is the circle's start up to 0.37; there the spin
turns back (its template's speed 1.1 -> 0.26 cm a sample over four states) while the circle goes
on at its pace. Among twenty templates back to back the spin was taken on circles at 0.24-0.29
of itself, as true spins are (0.22-0.30: nothing tells them apart before the turn), and drove
4-6 ticks, its followed state waiting at its turn (0.28-0.29) while the input went on up the
circle at its speed; on true spins the input slows there with the template (0.28-0.6 cm a
sample against 1.1-1.6 before). The overrun did not stop it: its size estimate grew 1.05 ->
1.36 over those samples (:data:`~behaviors.mop.overrun.GROWN` spares that), and its progress
kept pace until the last ticks.

So the best action is not shown while (:func:`outpaces`, at this sample and at the one before:
the follower's :meth:`~behaviors.mop.follower_validity.Validity._overruns`, the group's
:func:`~behaviors.mop.member_validity.overruns`) its template slows at the followed state to
under :data:`SLOW` of its speed :data:`SLOW_BACK` states earlier, the followed state advanced at
most :data:`STALL` states over the last :data:`STALL_SAMPLES` samples, and the input's speed
over the last :data:`RECENT` samples is at least :data:`KEEP` of its speed over the
:data:`EARLIER` samples before them (and at least :data:`MOVED` of a sigma a sample), and the
input lies past the followed state the way the template came to it.
Held out, at one sample alone (SLOW 0.4) it hid the spin on circles (wrong runs 4 -> 2 on seeds
110 and 112) but also 16 true ticks, each alone: a kick wrist, a punch and dance ankles and a
wave slowing at their turns while the performer still kept speed short of them, a held punch,
and true spins redrawn bent, taken at 0.26 and waiting at 0.29 (input 0.9-1.2 sigma a sample:
the same figures as the circles' 0.8-0.9); valid after 30% fell by 0.0001-0.0002. Over two
samples in a row none of those but one dance ankle remained (its template's step 0.07 against
0.18 four states back; the spin's 0.08 against 0.37): SLOW 0.3 spares it.

That left the spin's first 1-3 ticks past its turn: its followed state still advanced 1-3
states a sample into it (0.277 -> 0.29), over :data:`STALL`, while the input went on up the
circle. So it is also not shown (:func:`turns_on`, this sample alone, whatever the advance)
where the input's step over the last two samples heads off the template's way from the followed
state on (two states) by a cosine under :data:`TURNED` (circles -0.66 to -0.80; before the turn
0.93-0.99), the input keeps its speed past the state as above, the size estimate grew by
:data:`TURN_GROWN` since the sample before (circles 1.044-1.093: the follower stretches its size
to the input while its state waits) and the template turns there moving, a loop
(:data:`TURN_LOOP`: the spin keeps 0.21 of its speed). Without the growth and the loop, 27 true
ticks of the tuned sections were hidden (run wrist, jump wrist, crawl, punch, kick, wave, most
at full stops, 0.03-0.12, the follower ahead of its performer); with the growth alone 4 (0.03-
0.08); with both none. Held out, true spins redrawn bent are still hidden 1-2 ticks at 0.25-0.28
of them, as the circles (before the 30% the targets count). ``bench/follow_seeds.py
--sections=sized,unrelated,sequences``: twenty templates' longest wrong run 107-112 3/6/3/4/5/3
-> 3/5/3/2/4/2, 101-106 4/5/3/2/2/4 -> 4/3/3/2/2/4; every other figure equal.
``bench/follow_quality.py``: every figure equal.

Measured and not kept (the shown valid replayed per rule over one recorded run, 107-112,
``--sections=sized,sequences``): a new action not shown, until shown once, while its followed
state lies within A states before a turn of its template of over T degrees in its first 30%, so
that the spin waits for its turn. A 6, T 120: twenty templates' longest wrong run 108 5 -> 3, 111
4 -> 2, but six gestures within 20% 0.109 -> 0 (every drawn gesture turns in its first 30%),
twenty 0.313 -> 0.203, sized valid after 30% 0.9070 -> 0.9053; A 3-4, T 90-120: no run shorter,
the same losses smaller. The take comes before the turn on true spins as on circles.

That left the spin's ticks *before* its turn (``bench/follow_seeds.py --sections=sequences``,
traced per tick: 102 3, 108 5, 111 4 ticks on circles' 0.31-0.39): taken at 0.24 of itself, its
template slowing into the turn from 0.26-0.27 (its slowest step 0.21 of its speed four states
before at 0.277-0.289), its followed state still advancing 1-3 states a sample (over
:data:`STALL`; on 108 its size stretching 1.12 -> 1.41), while the input on the circle
*quickens* (1.1-1.6 times its speed over the :data:`EARLIER` samples; on true spins it slows
with the template). So an action under :data:`QUICK_EARLY` of its progress is not shown either
(:func:`quickens`, this sample alone) where its template slows (:data:`SLOW`) and the input,
past its followed state, moves at least :data:`QUICKEN` times as fast as before.
``bench/follow_seeds.py --sections=sized,unrelated,sequences``: twenty templates' longest wrong
run 101-106 4/3/3/2/2/3 -> 4/2/3/2/2/3, 107-112 3/5/3/2/4/3 -> 3/3/3/2/2/3 (108's 3 is the
punch ankle on a getup wrist, :mod:`~behaviors.mop.halts`); every within-20% and by-the-reach
share, six gestures' run and sized valid after 30% at 0.7-1.4x identical on all twelve seeds,
unrelated told worst 102 .0414 -> .0336, 103 .0540 -> .0434, 112 .0392 -> .0322.
Its price: it also hides true ticks before 0.3 where the follower leads its performer into a
slowing stretch at speed (``--sections=sized``, seeds 101 and 108: 1-2 ticks of waves at
0.22-0.26, kick wrists at 0.27-0.30, a spin at 0.26, a dance ankle at 0.07-0.09; their ratios
1.15-2.7, the circles' 1.1-1.6), none after 30%; and it hides 5-7 wrong ticks of the spin on
each seed's sized circles. ``bench/follow_quality.py``: unrelated told worst .0534 -> .0492,
after a gesture told worst .0721 -> .0617 (held-out .0716 -> .0664); but tuned twenty templates
recognised by the reach + 0.05 0.281 -> 0.250 (one gesture: a run or dance wrist hidden a tick
at 0.25-0.27, ratios 1.5-2.9), the option draws' six gestures recognition median .2555 ->
.2594, held-out bent 10% valid after 30% .4730 -> .4719. A higher :data:`QUICKEN` does not
separate them (true ticks hidden at 1.15-2.9, circles 1.1-1.6).

That left held-out seed 108's spin on a circle drawn 1.2x (twenty templates back to back, its
sixth sequence; the only wrong run over 2 ticks an observer could tell on seeds 101-112): taken
at 0.24 of itself, it drove 3 ticks at 0.31-0.34 of the circle (3.2-4.1 mm from every start of
the spin at ``bench/spotting_reach.py``'s 2 mm) with every gate passed (probable at 1.00 on
7.7-7.9 nats over the circle, whose size estimate lagged at 1.04-1.06, leading in shape), its
followed state (22.0 / 22.7 / 23.5) a state or more short of where its template slows (state
24: its step 0.21 of its speed four states before; at the followed state 1.67 / 1.32 / 0.72),
the input past it and quickening (1.3-1.5 times), its size stretching 1.10 -> 1.15 (1.2-1.5% a
sample): :func:`quickens` read the slowing only on the 4th tick. So it reads the next state too
(:data:`QUICK_AHEAD`) while the size grew by :data:`QUICK_GROWN` since the sample before (the
follower stretching its size to the input, as :data:`TURN_GROWN`). ``bench/follow_seeds.py``
(seeds 101-106 and 107-112, every section): 108's twenty avoidable and longest wrong run 3 ->
2, every other figure identical; ``bench/follow_quality.py``: every figure identical.
Measured and not kept: the next state read whatever the size: 102's run 2 -> 1 as well, after a
gesture and unrelated told shares lower (unrelated told 103 .0434 -> .0397, 111 .0319 -> .0283), but
sized valid after 30% lower on 102, 105, 109 and 111 (.9198 -> .9194 on 105), holds' valid after
30% .9580 -> .9570 (held-out .9625 -> .9618) and the option draws' wave recognised a tick later
(six gestures' recognition median .2443 -> .2458); 4 states ahead: the same, 105 .9189. Nor
does the size's growth alone tell a wrong run's 3rd tick: grown 1% a sample over 3 samples, it
marks 6 of the wrong ticks an observer could tell back to back (the spin on circles, 108 and
110; the tuned circle on a punch) and 125 of 17,589 true valid ticks (9 a recognition's first).
"""

from __future__ import annotations

import math

import numba

from behaviors.kernel_cache import compiled

#: The template slows at a state when its slowest step within one state of it is under this
#: share of its fastest of two steps :data:`SLOW_BACK` states earlier (0: never) ...
SLOW = 0.3
SLOW_BACK = 4
#: ... the followed state advanced at most this many states over the last
#: :data:`STALL_SAMPLES` samples ...
STALL = 0.8
STALL_SAMPLES = 2
#: ... and the input's mean speed over the last :data:`RECENT` samples is at least this share of
#: its mean speed over the :data:`EARLIER` samples before them ...
KEEP = 0.95
RECENT = 2
EARLIER = 4
#: ... which is at least this many sigma a sample (RMS per column): where the input crawls (a
#: joint's slow stretch) its speed is mostly the jitter's and keeps no profile.
MOVED = 0.5
#: The input's step turned off the template's way on by a cosine under this, the template's way
#: taken over this many states from the followed state (:func:`turns_on`; -1: never).
TURNED = -0.5
TURN_AHEAD = 2
#: ... while its size estimate grew by this factor over the last sample ...
TURN_GROWN = 1.04
#: ... at a turn the template takes moving (a loop: its slowest step there at least this share
#: of its speed before, as :data:`SLOW` reads it), not at a stop.
TURN_LOOP = 0.15
#: An action under :data:`QUICK_EARLY` of its progress is not shown where its template slows
#: (:data:`SLOW`) while the input, past its followed state, quickens to at least this share of
#: its speed (:func:`quickens`, whatever the followed state's advance; 0: never).
QUICKEN = 1.1
QUICK_EARLY = 0.3
#: ... its template slowing at the followed state or, while its size estimate grew by
#: :data:`QUICK_GROWN` since the sample before, within this many states ahead of it.
QUICK_AHEAD = 1
QUICK_GROWN = 1.01
#: The samples back :func:`outpaces` reads (the tempo's ring keeps at least these).
BACK = RECENT + EARLIER

_FA1, _FA2 = numba.float64[:], numba.float64[:, :]


@compiled(numba.float64(_FA2, numba.intp, numba.intp, numba.intp))
def _step(means, lo, off, j) -> float:
    """The length of the template's step from state ``j`` to ``j + 1`` (its spread)."""
    s = 0.0
    for c in range(means.shape[1]):
        d = means[lo + j + 1 + off, c] - means[lo + j + off, c]
        s += d * d
    return math.sqrt(s)


@compiled(numba.float64(_FA2, numba.intp, numba.intp, numba.intp))
def _slowed(means, lo, off, i) -> float:
    """The template's slowest step within one state of state ``i`` over its fastest of two
    steps :data:`SLOW_BACK` states earlier."""
    before = max(_step(means, lo, off, i - SLOW_BACK), _step(means, lo, off, i - SLOW_BACK + 1))
    least = min(_step(means, lo, off, max(i - 1, 0)), _step(means, lo, off, i),
                _step(means, lo, off, i + 1))
    return least / before if before > 0.0 else 1.0


@compiled(numba.boolean(_FA2, numba.intp, numba.intp, _FA1, _FA1, _FA1, _FA1, _FA1, _FA1, _FA1,
                        numba.intp, numba.float64, numba.float64, numba.float64, numba.intp))
def _keeps(means, lo, off, scale, uf, co, anchor, x, x_recent, x_earlier, i, size, sigma,
           keep, ahead) -> bool:
    """Whether the template slows at state ``i`` (from its first) or up to ``ahead`` states
    after it while the input, past ``i`` the way the template came, keeps ``keep`` of its speed
    (:func:`outpaces`' arguments)."""
    slow = False
    for j in range(i, i + ahead + 1):
        if _slowed(means, lo, off, j) < SLOW:
            slow = True
            break
    if not slow:
        return False
    # ... the input lies past the followed state the way the template came to it
    past = 0.0
    for c in range(x.size):
        z = ((x[c] - anchor[c]) / scale[c] + uf[c]) / size + co[c]
        a = means[lo + i + off, c]
        past += (z - a) * (a - means[lo + i - SLOW_BACK + off, c])
    if past <= 0.0:
        return False
    recent, earlier = 0.0, 0.0
    for c in range(x.size):
        r = (x[c] - x_recent[c]) / (scale[c] * size)
        e = (x_recent[c] - x_earlier[c]) / (scale[c] * size)
        recent += r * r
        earlier += e * e
    recent = math.sqrt(recent / x.size) / RECENT
    earlier = math.sqrt(earlier / x.size) / EARLIER
    return earlier >= MOVED * sigma and recent >= keep * earlier


@compiled(numba.boolean(_FA2, numba.intp, numba.intp, numba.intp, _FA1, _FA1, _FA1, _FA1,
                        _FA1, _FA1, _FA1, numba.float64, numba.float64, numba.float64,
                        numba.float64))
def outpaces(means, lo, n, off, scale, uf, co, anchor, x, x_recent, x_earlier, g, g_stall, size,
             sigma) -> bool:
    """Whether the input keeps its speed where the template (states ``lo`` .. ``lo + n - 1``,
    rows ``off`` on in ``means``) slows and its followed state ``g`` (from its first) waits
    (module docstring): ``x_recent``, ``x_earlier``: the samples :data:`RECENT` and
    :data:`BACK` back; ``g_stall``: the followed state :data:`STALL_SAMPLES` back; ``scale``:
    the template's spread per column, at ``size``; ``uf``, ``co``, ``anchor``: its mapping
    (as :func:`behaviors.mop.overrun.off_path2`); ``sigma``: the spread's sigma."""
    if SLOW <= 0.0:
        return False
    i = int(math.floor(g))
    if i - SLOW_BACK < 0 or i + 1 > n - 2 or g - g_stall > STALL:
        return False
    return _keeps(means, lo, off, scale, uf, co, anchor, x, x_recent, x_earlier, i, size, sigma,
                  KEEP, 0)


@compiled(numba.boolean(_FA2, numba.intp, numba.intp, numba.intp, _FA1, _FA1, _FA1, _FA1,
                        _FA1, _FA1, _FA1, numba.float64, numba.float64, numba.float64,
                        numba.float64))
def turns_on(means, lo, n, off, scale, uf, co, anchor, x, x_recent, x_earlier, g, size,
             size_before, sigma) -> bool:
    """Whether the input goes on away from where the template turns (:func:`outpaces`'
    arguments, but at this sample alone and whatever the followed state's advance): it
    slows at ``g`` and the input keeps its speed past it, its size estimate grew by
    :data:`TURN_GROWN` since the sample before (``size_before``: the follower stretches to the
    input rather than following it), and its step over the last :data:`RECENT` samples (at
    ``size``) heads off the template's way from ``g`` on (:data:`TURN_AHEAD` states) by a cosine
    under :data:`TURNED`."""
    if SLOW <= 0.0 or TURNED <= -1.0 or size < TURN_GROWN * size_before:
        return False
    i = int(math.floor(g))
    if i - SLOW_BACK < 0 or i + TURN_AHEAD > n - 1 or _slowed(means, lo, off, i) < TURN_LOOP:
        return False
    if not _keeps(means, lo, off, scale, uf, co, anchor, x, x_recent, x_earlier, i, size, sigma,
                  KEEP, 0):
        return False
    dot, ss, tt = 0.0, 0.0, 0.0
    for c in range(x.size):
        step = (x[c] - x_recent[c]) / (scale[c] * size)
        way = means[lo + i + TURN_AHEAD + off, c] - means[lo + i + off, c]
        dot += step * way
        ss += step * step
        tt += way * way
    return dot < TURNED * math.sqrt(ss * tt)


@compiled(numba.boolean(_FA2, numba.intp, numba.intp, numba.intp, _FA1, _FA1, _FA1, _FA1,
                        _FA1, _FA1, _FA1, numba.float64, numba.float64, numba.float64,
                        numba.float64, numba.float64))
def quickens(means, lo, n, off, scale, uf, co, anchor, x, x_recent, x_earlier, g, progress, size,
             size_before, sigma) -> bool:
    """Whether the input quickens where the template slows, at an action's start (``progress``
    under :data:`QUICK_EARLY`; :func:`outpaces`' arguments but ``g_stall``): the template slows
    at ``g`` (:data:`SLOW`; or up to :data:`QUICK_AHEAD` states after it where ``size`` grew by
    :data:`QUICK_GROWN` over ``size_before``, the sample before's) while the input, past it the
    way the template came, moves at least :data:`QUICKEN` times as fast over the last
    :data:`RECENT` samples as over the :data:`EARLIER` before them, however far the followed
    state advanced (module docstring)."""
    if QUICKEN <= 0.0 or progress >= QUICK_EARLY:
        return False
    i = int(math.floor(g))
    if i - SLOW_BACK < 0 or i + 1 > n - 2:
        return False
    ahead = min(QUICK_AHEAD, n - 3 - i) if size >= QUICK_GROWN * size_before else 0
    return _keeps(means, lo, off, scale, uf, co, anchor, x, x_recent, x_earlier, i, size, sigma,
                  QUICKEN, ahead)
