"""Turning: a new action is taken only while the input turns as its template does.

Part of the rules of :mod:`behaviors.mop.validity` (when a followed template may drive its
character); :class:`Turning` is a mixin of :class:`~behaviors.mop.follower.ActionFollower`.

Turning (:func:`turning`, 2-D spatial inputs; an option, off by default: ``turn_limit`` infinite):
a new action is taken only while the input's signed turning since the gesture began is within
``turn_limit`` radians (e.g. 1.3) of its template's
near the followed state (:data:`TURN_REACH` states either way; whole turns aside). Turning is
blind to size and tempo, and tells what the positions within a sigma do not: a diagonal is
no chord of a circle (the circle has turned by 2 radians at 37%), a mirrored path turns the
other way. Measured as above (after "not back before forward"): tuned 0.367 / 0.145, 0.9008
-> 0.363 / 0.135, 0.9006 (held-out 0.565 / 0.151, 0.8853 -> 0.472 / 0.136, 0.8838: the
held-out sized cost is 0.0015). Steps of 3 still radii, first direction after 3 steps, limit
1 rad: 0.344 / 0.123 but 0.873 (the first direction, taken in the eased start's jitter, was
off by up to a half turn: a figure eight at 1x and a circle at 0.7x never taken); first after
6 steps: 0.367 / 0.131, 0.898; limit 1.3: 0.367 / 0.135, 0.898 (held-out 0.476 / 0.139,
0.885); 1.6: 0.367 / 0.138, 0.8998; steps of 6 radii, first after 4: above. Off by default
because the full bench shows other costs at 1.3: gestures back to back among the twenty
held-out templates never recognised 0.125 -> 0.188 (the turning is counted from where the
gesture was spotted to begin, which in a stream can lie in the previous gesture's tail),
recognised within 20% 0.28 -> 0.25, 0.6x/1.5x recognised by the end 0.90 -> 0.85-0.875.

Measured and not kept (follower and group, turning read for every 2-D input): a template whose
first stroke is straight (no state before its first 0.5 rad of turning further than 0.08 of the
chord from it; the bend at 0.15 of it or later, not a corner of 1.4 rad) is not taken from 0.1
before that bend on until the input has turned 0.5 rad. The diagonal is the figure eight's first
stroke (held-out seed 109, six templates, 0.7/1/1.4x: 0.125/0.151/0.071 valid). Seeds 101-106
(``bench/follow_seeds.py --sections=sized,unrelated,sequences``): unrelated mean 0.0980 -> 0.0894
(102 0.0814 -> 0.0491), but valid after 30% at 0.7-1.4x lower on every seed (0.9022 / 0.8858 /
0.9057 / 0.8990 / 0.8903 / 0.8849 -> 0.8991 / 0.8851 / 0.9017 / 0.8897 / 0.8857 / 0.8785), tuned
0.9124 -> 0.9122; twenty back to back within 20% 101 0.344 -> 0.313, 102 0.281 -> 0.250.
Nor only from 0.1 before that bend up to it (past the bend the followed state itself shows the
template's shape; no wait for the input's turn): the diagonal on the eight 0 valid on every draw
(tuned seeds 5-11 x 3 sizes, 0-10 before), 109's worst 0.1154 -> 0.0912, 101-106 unrelated mean
0.0980 -> 0.0894, but valid after 30% 0.9000 -> 0.8980 (103 0.9129 -> 0.9102, 104 0.9028 ->
0.8940, 102 and 105 lower too), twenty back to back within 20% 101-103 lower by 0.03 each: the
cost is the window before the bend itself, where true performances are taken.
Nor only where the bend goes on turning (1 rad within 0.1 after it; the held-out walk wrist's
first stroke drifts 0.52-0.66 rad from 0.22 to 0.43 of it and is one stroke up to its turn back:
waiting there cost seed 104's sized 0.9028 -> 0.8940, the 1.4x wrist 0.80 -> 0.44), the bend at
0.3 of its template or earlier (the square's first side, to 0.375, not waiting), the wait ended
at the bend or at the input's turn: held-out only the figure eight waits. Seeds 101-112, same
sections: unrelated worst 101-106 0.1030 (103's mirrored square, the punch ankle's own stroke)
both, mean 0.0935 -> 0.0856 (102 0.0814 -> 0.0533, 105 0.0996 -> 0.0840); 107-112 worst 0.1154
-> 0.0912, mean 0.0954 -> 0.0800 (107 0.0914 -> 0.0666, 111 0.0918 -> 0.0691); 107-112 sized
and sequences identical; but 103 sized 0.9129 -> 0.9107 (a 0.7x eight paused 0.5 s near its
bend: 0.948 -> 0.724) and twenty back to back within 20% 101 0.344 -> 0.313. Waiting for the
input's turn past the bend as well: also 106 0.8910 -> 0.8908, 110 0.9066 -> 0.9064, 112 0.8950
-> 0.8942; ``bench/follow_quality.py``: after a gesture mean 0.0584 -> 0.0291 (a diagonal after
one 0.116 -> 0), held-out unrelated mean 0.0126 -> 0.0088, but six back to back recognised at
0.246 -> 0.284 (the eight 0.244 -> 0.305), 0.6/1.5x recognised by the end 0.975 -> 0.950,
held-out aspect 1.2 0.427 -> 0.404, bent 10% 0.469 -> 0.466.
The wait ended at the bend, with a take on the input's own bend (followed at or past its wait,
input turned 0.5 rad) holding a pause as one performed 0.3 of its path does (validity.stalls):
103's 0.7x eight, taken at 0.272 after its wait and paused 0.5 s at 0.316 with 0.045 carried,
had been invalid for the pause; spared, it drives through it. Seeds 101-112: sized identical
on every seed (0.9076 / 0.8938 / 0.9162 / 0.9028 / 0.8937 / 0.8910, 0.8925 / 0.8851 / 0.8938 /
0.9087 / 0.8989 / 0.8972), sequences identical but one figure, unrelated worst 107-112 0.1154 ->
0.0902 (109 0.0663, 107 0.0914 -> 0.0666), 101-106 mean 0.0935 -> 0.0856; but twenty back to back
within 20% 101 0.344 -> 0.313: that figure eight, from rest, recognised at 0.188 -> 0.272. It
was taken at 0.219 of the eight (size 0.77), the 1x diagonal at 0.216 (0.99): no window tells
them (one sample later, 0.196, is still within 20%, but it would take at most one of the 1x
diagonal's 14 valid samples of 93). The wait's cost is the eight's own recognition before its
bend (six back to back 0.246 -> 0.284, the eight 0.244 -> 0.297), with held-out aspect 1.2
0.427 -> 0.406, bent 10% 0.4704 -> 0.4696, held-out wrong valid over a pause 0 -> 0.005 (after
a gesture mean 0.058 -> 0.030). What is kept instead: the eight is taken as before and only
not shown in the last 0.03 before its bend while the input has not turned (:mod:`bends`).
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.mop import bends

#: Turning (below) is measured along steps of this many still radii (the smallest column's)...
TURN_STEP = 6.0
#: ... and the first direction once the path left its start by this many steps.
FIRST_TURN_STEPS = 4.0
#: Samples within this many states of the followed one whose turning may match the input's.
TURN_REACH = 3


def turning(path: np.ndarray, step: float) -> np.ndarray:
    """Per sample of a 2-D path (n, 2), its signed turning (radians) since its first direction:
    the direction of each step of length ``step`` (the first :data:`FIRST_TURN_STEPS` long)
    against the last one's, summed."""
    out = np.zeros(len(path))
    ref, h0, turn = path[0], None, 0.0
    for i, p in enumerate(path):
        turn, h0, ref = turn_step(p, ref, h0, turn, step)
        out[i] = turn
    return out


def turn_step(x: np.ndarray, ref: np.ndarray, heading: float | None, turn: float,
              step: float) -> tuple[float, float | None, np.ndarray]:
    """One sample ``x`` of :func:`turning`: (turning, last direction or None, last step's end)."""
    d = x - ref
    if math.hypot(d[0], d[1]) <= (step if heading is not None else FIRST_TURN_STEPS * step):
        return turn, heading, ref
    h = math.atan2(d[1], d[0])
    if heading is not None:
        turn += (h - heading + math.pi) % (2.0 * math.pi) - math.pi
    return turn, h, x


def turn_fits(turns: np.ndarray, turn: float, limit: float) -> bool:
    """Whether the input's turning ``turn`` is within ``limit`` radians of the template's at
    some of the states ``turns`` (around the followed one), whole turns aside (a hairpin is
    +pi or -pi by the jitter)."""
    off = np.abs((turns - turn + math.pi) % (2.0 * math.pi) - math.pi)
    return bool(off.min() <= limit)


class Turning:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: the input's turning against
    its template's (:func:`turning`)."""

    def _setup_turning(self) -> None:
        """Per state, its template's turning (:func:`turning`), for 2-D spatial inputs only, and
        whether it lies just before a straight first stroke's bend (:mod:`~behaviors.mop.bends`:
        measured whatever ``turn_limit``)."""
        self._turn_step = TURN_STEP * float(self._still_radius.min())
        b = self.bank
        self._turn = None
        self._before_bend = np.zeros(len(b.means))   # (bends.before_bends)
        self._waits = np.zeros(len(b.means))   # (bends.waits)
        if self.dim == 2 and self.invariance != "none":
            path = [b.template(k) * b.scale[k] + b.center[k] for k in range(len(self.names))]
            self._turn = np.concatenate([turning(p, self._turn_step) for p in path])
            self._before_bend = bends.before_bends(self._turn, b.source, b.starts, b.lengths,
                                                   np.concatenate(path))
            self._waits = bends.waits(b.source, b.starts, b.lengths, np.concatenate(path))

    def _turned(self, x: np.ndarray, bi: int, g: float) -> bool:
        """After sample ``x``: the input's turning since the gesture began, and whether it fits
        template ``bi``'s near its followed state ``g`` (bank index)."""
        if self._turn is None:
            return True
        if self._turn_ref is None:
            self._turn_ref = (self._anchor if self._anchor is not None else x).copy()
        else:
            self._turn_in, self._turn_h, self._turn_ref = turn_step(
                x, self._turn_ref, self._turn_h, self._turn_in, self._turn_step)
        lo = int(self.bank.starts[bi])
        hi = lo + int(self.bank.lengths[bi]) - 1
        c = int(g)
        return turn_fits(self._turn[max(lo, c - TURN_REACH):min(hi, c + TURN_REACH) + 1],
                         self._turn_in, self.turn_limit)

    def _strays(self, bi: int, c: int, x: np.ndarray) -> bool:
        """Whether template ``bi``, followed at state ``c`` (bank index), is not shown while the
        input ``x`` draws a straight stroke its path so far strays from
        (:func:`bends.strays <behaviors.mop.bends.strays>`; 2-D spatial inputs)."""
        if self._turn is None or self._anchor is None or self._stroke_bent:
            return False
        lo = int(self.bank.starts[bi])
        path = self._rel[lo:c + 1] * self._units
        samples = np.asarray(self._taken[:-1]).reshape(-1, self.dim) * 1.0
        out = bends.strays(path, float(self._size[bi]), samples, x - self._anchor)
        # (once the input left its chord, it draws no straight stroke until a new attempt)
        self._stroke_bent = out is None
        return bool(out)
