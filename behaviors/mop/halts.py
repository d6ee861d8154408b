"""The input halting where the template goes on: an action just taken at its start is not
shown while its performer stops short in a stretch its template goes through at speed (follower
and group alike, beside the overrun's veto, :mod:`behaviors.mop.overrun`; only what is shown:
the rules go on).

The held-out getup wrist begins with a straight stroke of about 6 cm, then waits (0.13-0.30 of
it); the punch ankle's first 0.27 is the same stroke at the same size, and its template goes on
at speed (0.5-0.7 cm a state) for 15 cm. Among twenty templates back to back the punch was
taken on getups at 0.23-0.24 of itself, as the stroke ended, and drove 4-7 ticks while the
input stood at the stroke's end (its steps 0.3-2 mm against 4-7 mm before) and its followed
state crawled (0.2-0.6 states a sample) toward where its template went on. The rest rule
(:func:`behaviors.mop.validity.stalls`) did not stop it: the input drifts on with the getup's
wait (1-2 mm a sample), never within the rest's radii.

So the action driving is not shown while (:func:`halts`) it has not carried its performer
:data:`~behaviors.mop.validity.CARRY_FIRST` past where it began driving, its progress is under
:data:`EARLY`, its template's slowest step from the followed state on (its step and the
next) is at least :data:`GOES_ON` of its fastest of two steps ``SLOW_BACK`` states earlier, and
the input's mean speed over the last ``RECENT`` samples, both along the template's direction
there and its own, is under :data:`HALT` of its mean speed over the ``EARLIER`` samples before
them (along the direction at least :data:`MOVED` of a sigma a sample, and not going back).
Measured (``OPENBLAS_NUM_THREADS=1 bench/follow_seeds.py --sections=sized,unrelated,sequences``,
held-out seeds 107-112; every variant replayed on the same followed ticks, as the rule only
hides): twenty templates' longest wrong run on 103 7 -> 3 (its seventh sequence; 108's first
getup 6 -> 3 lies under 108's spin, 6), unrelated told worst .0842 -> .0818 (104) and .0666 ->
.0640 (107-112; mean .0511 -> .0486), every other figure identical (sized valid after 30% at
0.7-1.4x mean .9062 / .9036, the six gestures' runs and shares within 20%).
Its price, taken: ``bench/follow_quality.py`` held-out pauses' valid share .9467 -> .9458 (an
action just taken, then paused where its template goes on, reads as the getup's wait does);
its own strokes told valid at most .0981 -> .0949.
Measured and not kept (107-112 / 101-106): the speed along the direction alone (the first
form), valid after 30% at 0.7-1.4x mean .9000 / .9040, every seed lower: figure eights at 0.30
whose followed state lags at 0.22, before the turn the performer already took (the input turns
keeping its speed); that, not going back and before 0.3: .9034 / .9061; both speeds without
:data:`EARLY`: .9019 / .9053; both under 0.6 with :data:`EARLY`: .9035 / .9062.

Where the template also goes on over :data:`AHEAD` of its progress past the followed state (its
slowest step there at least :data:`GOES_ON` of its speed before), the input halts under
:data:`HALT_ON` instead. The punch on the getup still drove 3 ticks on held-out 103 and 108: its
input slowed to 0.56-0.61 of its speed (along / own) at its third tick, over :data:`HALT`, and
its template goes on for 0.1 of its progress and more (its steps there 0.9-1.4 of its speed
before). :data:`HALT` 0.65 everywhere hid it, but also a walk wrist followed at 0.253 whose
performer was at 0.387 (sized 108, valid after 30% at 0.7-1.4x .90252 -> .90229): the input
slowed in its template's turn, which the followed state, far behind, had not reached (the
template's steps 2-5 states ahead 0.64-0.40 of its speed before). Reading the slowest step over
0.1 ahead for :data:`HALT` too (0.65 everywhere) spared the walk, but also spared an unrelated
wander shown as a wave where the rule within one state hid it (the wave's template slowing 2
states ahead, 0.42; the input along its way 0.04 of its speed before): unrelated told 109 .0640
-> .0663. So the rule within one state is kept as it was, and the wider share only added where
the template goes on ahead: it hides every tick it hid, and more. ``bench/follow_seeds.py
--sections=sized,unrelated,sequences``: twenty templates' longest wrong run 4/2/3/2/2/3 ->
4/2/2/2/2/3 (101-106; 108's punch is hidden a tick sooner under its spin's run of 3, 112's lies
under :data:`GOES_ON`: its template slows to 0.688 there), unrelated told 104 .0818 -> .0795, 107
.0557 -> .0534; every other figure the same on 101-112 (sized valid after 30% on every seed).

The template's slowest step is read from the followed state on (the steps at it and after it),
not the step behind it too: the punch ankle's template slows to 0.69 of its speed over one step
(states 17 -> 18 of 64, 0.27-0.28 of it) and goes on at 0.76-1.6 after it. Taken on a getup
wrist as the getup's stroke ended (held-out 112) and followed past that step (18.4-18.7), it
drove 3 ticks while the input halted (along / own 0.53 / 0.54, 0.50 / 0.58 of its speed):
the step behind, already passed, kept the rule off. :data:`GOES_ON` 0.65 hid it, but also a
true punch followed *on* that step (sized 107, 17.1-17.4, its performer paused at 0.334:
valid after 30% .92134 -> .92112), which the rule read from the followed state on still spares.
It only widens where the rule applies (it hides every tick it hid). ``bench/follow_seeds.py
--sections=sized,unrelated,sequences``: twenty templates' longest wrong run 107-112
3/3/3/2/2/3 -> 3/3/3/2/2/2, every other figure the same (131 figures; 101-106: all 133 the
same). Its price, taken: ``bench/follow_quality.py`` held-out pauses' valid share .9507 ->
.9473 (a figure eight taken at 0.297 and paused there at once, its template's step behind the
followed state 0.62 of its speed, hidden 3 ticks of its pause until it passed 0.3: a pause at a
take reads as the getup's wait); its 683 other figures the same.
That price is taken back by :data:`DRIFTS`: where only the step behind the followed state slows
(the ticks the reading from the followed state on adds), the input halts only while it still
drifts, its own speed at least 0.2 of its speed before. The getup's wait under 112's punch
drifts on (0.54-0.58 of its speed), the paused figure eight stops (0.02-0.07); no other tick of
the recorded calls (1820, held-out 107, 108, 112 and the pauses) is read there. Held-out pauses'
valid share .9473 -> .9507, every other ``bench/follow_quality.py`` figure the same (683), and
every ``bench/follow_seeds.py --sections=sized,unrelated,sequences`` figure on 101-112 (112's
longest wrong run stays 2).
"""

from __future__ import annotations

import math

import numba

from behaviors.kernel_cache import compiled
from behaviors.mop import speed_profile
# the same samples as the speed profile's (RECENT, EARLIER; BACK: the tempo's ring keeps them)
from behaviors.mop.speed_profile import _FA1, _FA2, BACK, EARLIER, RECENT, SLOW_BACK, _step

#: The input halts when its mean speed the template's way (along its direction at the followed
#: state; not back) and its own mean speed over the last ``RECENT`` samples are each under this
#: share of theirs over the ``EARLIER`` samples before them (0: never) ...
HALT = 0.5
#: ... which is at least this many sigma a sample (the template's spread, at the size) ...
MOVED = 0.25
#: ... while the template goes on: its slowest step from the followed state over the next
#: state (the steps at it and after it) is at least this share of its fastest of two steps
#: ``SLOW_BACK`` states earlier.
GOES_ON = 0.7
#: ... before this progress of the action (its start, which other actions' paths share).
EARLY = 0.3
#: Where the template also goes on over this share of its progress past the followed state (its
#: slowest step there at least ``GOES_ON`` of its speed before), the input halts under
#: :data:`HALT_ON` of its speed instead of :data:`HALT`.
AHEAD = 0.1
HALT_ON = 0.65
#: Where the template's step behind the followed state slows under :data:`GOES_ON` (the steps
#: at it and after it do not), the input halts only while its own mean speed over the last
#: ``RECENT`` samples is still at least this share of its speed before: the getup's wait
#: drifts on (0.54-0.58), a performer paused at the take stops (0.02-0.07).
DRIFTS = 0.2


@compiled(numba.boolean(_FA2, numba.intp, numba.intp, numba.intp, _FA1, _FA1, _FA1, _FA1, _FA1,
                        numba.float64, numba.float64, numba.float64, numba.float64),
          speed_profile)
def halts(means, lo, n, off, scale, units, x, x_recent, x_earlier, g, progress, size,
          sigma) -> bool:
    """Whether the input halts where the template (states ``lo`` .. ``lo + n - 1``, rows
    ``off`` on in ``means``) goes on at its followed state ``g`` (from its first; ``progress``:
    the action's, 0..1; module docstring): ``x_recent``, ``x_earlier``: the samples ``RECENT``
    and ``BACK`` back; ``scale``: the template's spread per column, at ``size``; ``units``: the
    features' units (the input's own speed); ``sigma``: the spread's sigma. Whether the action
    carried its performer is the caller's."""
    if HALT <= 0.0 or progress >= EARLY:
        return False
    i = int(math.floor(g))
    if i - SLOW_BACK < 0 or i + 1 > n - 2:
        return False
    before = max(_step(means, lo, off, i - SLOW_BACK), _step(means, lo, off, i - SLOW_BACK + 1))
    # (from the followed state on: the step behind it is passed; module docstring)
    least = min(_step(means, lo, off, i), _step(means, lo, off, i + 1))
    if least < GOES_ON * before:
        return False
    # ... and where only the step behind it slows, while the input still drifts (DRIFTS)
    floor = DRIFTS if _step(means, lo, off, i - 1) < GOES_ON * before else 0.0
    # ... under HALT_ON where it goes on over AHEAD of its progress too
    share = HALT_ON
    for j in range(i + 2, min(n - 2, i + 1 + int(math.ceil(AHEAD * (n - 1)))) + 1):
        if _step(means, lo, off, j) < GOES_ON * before:
            share = HALT
            break
    # the input's way along the template's direction at the followed state (its spread, at
    # the size) and its own speed (in its units): over the last RECENT samples and the EARLIER
    # before them
    norm, recent, earlier, own, own_before = 0.0, 0.0, 0.0, 0.0, 0.0
    for c in range(x.size):
        d = means[lo + i + 1 + off, c] - means[lo + i - 1 + off, c]
        norm += d * d
        recent += d * (x[c] - x_recent[c]) / (scale[c] * size)
        earlier += d * (x_recent[c] - x_earlier[c]) / (scale[c] * size)
        own += ((x[c] - x_recent[c]) / units[c]) ** 2
        own_before += ((x_recent[c] - x_earlier[c]) / units[c]) ** 2
    if norm <= 0.0:
        return False
    norm = math.sqrt(norm)
    recent, earlier = recent / norm / RECENT, earlier / norm / EARLIER
    own, own_before = math.sqrt(own) / RECENT, math.sqrt(own_before) / EARLIER
    return (earlier >= MOVED * sigma and 0.0 <= recent < share * earlier
            and floor * own_before <= own < share * own_before)
