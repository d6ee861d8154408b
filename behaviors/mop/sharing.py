"""Shared starts: how far each template's path is the start of another's at some size.

The line's outward stroke is the square's first side and the start of the circle: until the
performer turns, nothing in the input tells them apart, at any size. :func:`shared_until` finds,
for every pair of templates (A, B), the last state of A whose path from A's start lies, state by
state in order, within a radius of B's path from B's start scaled by one of a range of sizes (B may
run up to ``skip`` states per state of A, or stay); spotting
(:meth:`~behaviors.mop.spotting.GestureSpotting._shares`) keeps a new action from driving while its
followed state is within its start shared with another template the input still fits. B's states
are taken as points: where they lie farther apart than twice the radius at a size (a fast stretch),
the sharing ends there, on the side of holding fewer actions back (measured with segments between
B's states instead: the line's start shared with the square up to 0.58 of it, past its turn, as its
return runs back along the same side). Compiled (numba): 20 templates of 30-110 states take a few
milliseconds (numpy: 1.4 s).

Shared starts (``ActionFollower(share_radius=...)`` in still radii, 0 = off;
:meth:`~behaviors.mop.spotting.GestureSpotting._shares`, :func:`shared_until`): a new action does
not drive while its followed state is within the stretch of its start that is the start of another
template at some size (from the size range's smallest to largest ratio), as long as that other
template is neither refused nor off its path nor going back (its followed progress
:data:`~behaviors.mop.spotting.SHARE_BACK` below its highest since the gesture began): the input
cannot tell them apart, so both are only shown as ``likely``. This is what the shape lead does not
catch where the other template's evidence is already below
:data:`~behaviors.mop.shape_lead.RIVAL_PROBABILITY` (the square's falls to 0.001 on its first side,
since its broader eased start lags the input): without it the line drives the square's first side
(every wrong run over 2 ticks among the six gestures back to back: 3-10 ticks, all where no
observer could yet tell them apart). On by default at 3 still radii, with a gesture that ends where
it returned also while its action was held back
(:meth:`~behaviors.mop.spotting.GestureSpotting._returned`): ``bench/follow_quality.py`` (tuned /
held-out), six gestures back to back, longest wrong-valid run 10 / 7 -> 2 / 2 (other than the ended
gesture's 10 / 7 -> 0 / 0), never recognised 0 / 0, the line recognised at 0.33 / 0.38 -> 0.45 /
0.53 (after its turn; the observer tells it from the square at 0.35), the square 0.40 / 0.41 ->
0.41 / 0.42; twenty templates longest wrong run 7 / 12 -> 3 / 11, within 20% 0.344 / 0.344 -> 0.344
/ 0.313; ``--sections=sized,holds,unrelated``: valid after 30% of gestures at 0.7-1.4x 0.9112 /
0.9033 -> 0.9005 / 0.9023 (the line at 1.0-1.4x is valid only after its turn, and some clips'
starts are shared: punch and spin, 0.24-0.29 of them), unrelated motions mean 0.0688 / 0.0772 ->
0.0659 / 0.0723, worst 0.258 / 0.418 -> 0.258 / 0.414, holds unchanged. Before the held-back return
rule it was off: a line held back until its turn, then followed backwards at the wrong size, never
reached its end, and the square after it began inside its attempt (held-out: a zigzag drove 8 ticks
of it).
Measured and not kept: 4 still radii (the spin wrist's start shared with the circle up to 0.26 of
it instead of 0.17, the punch ankle's with the getup wrist 0.29 instead of 0.14). ``bench/
follow_seeds.py --sections=sized,unrelated,sequences`` (101-106): twenty templates back to back,
longest wrong run 4, 5, 7, 2, 2, 4 -> 4, 2, 2, 2, 2, 4 (the spin on a circle and the punch on a
getup, held until they part), but valid after 30% at 0.7-1.4x lower on every seed (mean 0.9000 ->
0.8933; 102 0.8933 -> 0.8843) and twenty within 20% on 102 0.281 -> 0.250.
What holds the six gestures back to back past the observer's reach + 0.05
(``bench/follow_quality.py``'s sequences, tuned / held-out 101, per tick with
``bench.spotting_reach.gate_state``): 20 of 32 each; progress summed from the reach to recognition
while each check failed: this shared start 1.26 / 1.60 (the line, 0.10-0.65 past its reach),
probability and best 0.92 / 0.76 (the commitment waits for coverage: covered, probable and best
clear on one sample in 7 / 7), coverage 0.89 / 0.72, the lead 0.61 / 0.59, the confirmation's
sample 0.57 / 0.57. On the line the square waits at its corner (its state 25.4-26.1; its own
stretch shared with the line ends at 25, the line's at 20), its size rising 1.05 -> 1.31 and its
evidence given up. Measured and not kept: a rival past its own stretch of the start no longer holds
the action (``shared[b, k]`` read at b's followed state too). Alone: held-out twenty's longest
avoidable wrong run 2 -> 10 (a getup wrist on a punch ankle, 0.18-0.27 of it: the punch ankle, 0.98
probable, passes its stretch first). Only while that rival is below
``shape_lead.RIVAL_PROBABILITY``: the held-out line 0.525 -> 0.438 (median), six past the reach
0.085 / 0.094 -> 0.084 / 0.079, twenty 0.098 / 0.084 -> 0.093 / 0.084, every within-20% and
by-reach share unchanged (the line freed at 0.38-0.45, recognised at 0.40-0.48 with the
confirmation), but held-out unrelated worst 0.091 -> 0.116 (the punch ankle on mirrored strokes
among twenty), the tuned triangle among six 0.042 -> 0.065 (the line on its first stroke, its
start).
Per tick from the line's reach (0.35) to its recognition (``bench.spotting_reach.gate_state``;
``bench/follow_quality.py``'s sequences, tuned and held-out 101, six and twenty): this shared
start holds every tick but the confirmation's last, the lead too up to 0.34-0.40 in half of them.
The square waits at its corner (25.4-26.2), its misfit (16 samples) 0.1-0.45 sigma as it gets
there, rising 0.1-0.15 a sample; the input's distance off its path at one sample is 0.6-1.2
sigma a sample or two after it gets there, 1.3-2.4 after. Measured and not kept: a rival past
its stretch whose misfit is beyond 0.5 / 0.4 sigma no longer holds the action: the held-out line
0.525 -> 0.445 / 0.438, no share moved, at 0.4 held-out twenty's avoidable wrong run 2 -> 6. Nor
one the input strays from at that sample by more than 1.0 sigma (``|u / size - v|`` as the
misfit reads it) where it does not stray from the action's path: the six by reach + 0.05 0.500 /
0.500 -> 0.531 / 0.531, the line 0.455 / 0.525 -> 0.435 / 0.445, the circle 0.262 / 0.266 ->
0.248 / 0.250, no target crossed; ``bench/follow_seeds.py`` (whatever the action's stray)
101-106 / 107-112 six by reach + 0.05 mean 0.391 / 0.411 -> 0.443 / 0.464, but own strokes told
valid worst 0.045 / 0.076 -> 0.116 / 0.113 (105 0.116, 106 0.102, 108 0.113 either way; on
106 the held-out backflip left ankle's among twenty, under 0.03 -> 0.102): a straight stroke is
freed where its rival's path turns off it. At 1.2 sigma 105 0.107, 106 0.102; read only at the
end of the rival's stretch 0.116, 0.102, 0.113 (six by reach + 0.05 mean 0.417 / 0.432); at 0.8
sigma held-out six's avoidable wrong run 0 -> 2.
The figure eight's recognition minus reach (0.134 / 0.117) is against its reach among the six
(0.11); against the diagonal's (0.21) it is 0.03 / 0.02: recognised by reach + 0.05 in 25 of 27
(tuned and held-out 101-103), the confirmation's sample the last gate in 26.
At the first sample every check passes (before the confirmation's) the true gestures and the
unrelated strokes after a gesture read alike (medians, tuned and held-out 101; the lead tuned):
lead 16.8 / 13.1 nats, commitment's fit 2.1 / 2.3 still radii RMS, last drift 1.7 / 1.7, size
change over 3 samples 0.007 / 0.005, probability 0.98 / 0.98; only strokes from rest advance slower
(0.025 against 0.052 of progress over 3 samples), and the lead's growth on that sample tells
them apart more (:data:`~behaviors.mop.shape_lead.CONFIRM_GAIN`)."""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled

_F1 = numba.float64[::1]
_F2 = numba.float64[:, ::1]
_I1 = numba.intp[::1]


def shared_until(rel: np.ndarray, starts: np.ndarray, lengths: np.ndarray, sizes: np.ndarray,
                 radius: np.ndarray, skip: int) -> np.ndarray:
    """(K, K) state indices: entry [a, b] is the last state of template ``a`` whose path up to
    there follows template ``b``'s scaled by one of ``sizes`` within ``radius`` in every
    column (d,), or template ``b``'s row of it (K, d), both from their first points; -1 on the
    diagonal. ``rel`` (states, d): every template's states relative to its first (raw units),
    template k at ``starts[k]``, ``lengths[k]`` states."""
    by = np.empty((len(starts), rel.shape[1]))
    by[:] = radius
    return _shared_until(np.ascontiguousarray(rel, dtype=float),
                         np.ascontiguousarray(starts, dtype=np.intp),
                         np.ascontiguousarray(lengths, dtype=np.intp),
                         np.ascontiguousarray(sizes, dtype=float), by, int(skip))


# (numba's ``njit(cache=True, nogil=True)``, in the shared cache: see tabletop.drawing.dirty.KERNEL)
@compiled(numba.intp[:, ::1](_F2, _I1, _I1, _F1, _F2, numba.intp), error_model="python")
def _shared_until(rel: np.ndarray, starts: np.ndarray, lengths: np.ndarray, sizes: np.ndarray,
                  radius: np.ndarray, skip: int) -> np.ndarray:
    """:func:`shared_until` compiled, ``radius`` (K, d) per template ``b``."""
    k, d = starts.size, rel.shape[1]
    out = np.full((k, k), -1, dtype=np.intp)
    reach = np.zeros(int(lengths.max()), dtype=np.bool_)
    grown = np.zeros_like(reach)
    for a in range(k):
        sa, na = starts[a], lengths[a]
        for b in range(k):
            if a == b:
                continue
            sb, nb = starts[b], lengths[b]
            best = -1
            for s in sizes:
                reach[:nb] = False
                reach[0] = True
                lo, hi = 0, 0           # the states of b still reached lie within lo..hi
                last = -1
                for i in range(na):
                    top = min(hi + (skip if i else 0), nb - 1)
                    new_lo, new_hi = -1, -1
                    for j in range(lo, top + 1):
                        r = reach[j]
                        if i:
                            for o in range(1, min(skip, j - lo) + 1):
                                r = r or reach[j - o]
                        if r:
                            for c in range(d):
                                if abs(s * rel[sb + j, c] - rel[sa + i, c]) > radius[b, c]:
                                    r = False
                                    break
                        grown[j] = r
                        if r:
                            new_hi = j
                            if new_lo < 0:
                                new_lo = j
                    if new_lo < 0:
                        break
                    reach[lo:top + 1] = grown[lo:top + 1]
                    lo, hi = new_lo, new_hi
                    last = i
                    if last == na - 1:
                        break
                best = max(best, last)
                if best == na - 1:
                    break
            out[a, b] = best
    return out
