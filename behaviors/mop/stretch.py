"""States stretched along a fast stretch of their template (the observation of each state).

A template is one recording at the input's rate, so where the recorded motion is fast its states
lie far apart: the held-out backflip ankle's loop moves up to 7.3 sigma (in its own spread) from
one state to the next. A performer's sample between two such states lies 2-3.6 sigma from both,
so the forward's step likelihood there is that of a stray, whatever the progress: the true
action, followed on its path at the right size, was refused by its recent likelihood (beyond
``null_distance``) or lost best to a rival in its loop, and was valid after 30% of it 0.23-0.46
of the time on eleven of the held-out sized draws of seeds 101-112 (the largest class of the
draws valid under 0.5 there).

So each state's Gaussian (equation 1) is stretched along its template's path: the distance of a
sample from a state is its distance from a short segment through the state along the path's
direction there (the chord from the state before to the one after), of half-length
:data:`STRETCH_SHARE` of the nearer neighbour's gap, less :data:`STRETCH_FROM` sigma (what the
Gaussian covers anyway), never across a turn (the two gaps' directions at a cosine below
:data:`STRETCH_COS`), its density spread over its length (normalised as a point's is, so a
stretched state explains no more of the plane than a point: without it a kick wrist's stretched
states at 0.55x took 1.2x getup wrists, valid after 30% 0.95 -> 0.59). Where the states lie
closer than twice :data:`STRETCH_FROM`, the state is the paper's point Gaussian, to the bit
(:func:`~behaviors.mop.window_kernel.step_windows`); the follower and a group stretch alike.

Screened on the held-out sized draws (valid after 30% at 0.7-1.4x per seed, the draws of
``bench/follow_seeds.py --sections=sized``; point states 101-112 .9185 .9036 .9171 .9102 .9133
.9015 / .9166 .9003 .9088 .9164 .9029 .9123): :data:`STRETCH_FROM` 1 sigma, not normalised,
.9201 .9064 .9166 .9071 .9111 .9065 / .9141 .9004 .9096 .9203 .8986 .9144 (backflip draws
under 0.5: 11 -> 4); normalised .9195 .9101 .9170 .9103 .9117 .9077 / .9222 .9012 .9088 .9181
.8974 .9123 (111's roll wrist at 0.7x .82 -> .59, getup wrist at 1.4x .66 -> .32: rivals whose
moderately fast stretches, 2-4 sigma a state, now fit as well); 1.5 sigma: 102 .9090, 105 .9164,
107 .9223, 111 .9002; 2 sigma (kept): 102 .9090, 105 .9167, 107 .9213, 111 .9027: only the
sparsest stretches (states over 4 sigma apart: the backflip ankle's loop, the spinkick wrist,
the jump ankle) are stretched. ``bench/follow_seeds.py --sections=sized,unrelated,sequences``
(held-out): sized means .9107 -> .9131 (101-106: 101 .9185 -> .9201, 102 .9036 -> .9090, 105
.9133 -> .9167, 106 .9015 -> .9054, 103 and 104 the same) and .9095 -> .9109 (107-112: 107
.9166 -> .9213, 108 .9003 -> .9025, 109 .9088 -> .9100, 110 .9164 -> .9167); every unrelated and
sequences figure the same. Price, taken: 111 .90291 -> .90272 (its 0.7x backflip ankle .51 ->
.49, taken a sample later), 103's progress RMSE median .02301 -> .02302.
"""

from __future__ import annotations

import numpy as np

#: The stretch's half-length is this share of the gap to the nearer neighbouring state ...
STRETCH_SHARE = 0.5
#: ... less this many sigma (the Gaussian's own reach): states closer than twice this are points.
STRETCH_FROM = 2.0
#: No stretch where the path turns: the gaps before and after a state at a cosine below this.
STRETCH_COS = 0.7


def state_stretches(means: np.ndarray, starts: np.ndarray, lengths: np.ndarray,
                    sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """Per state of a bank (``means`` (S, d) standardised, templates at ``starts`` of
    ``lengths``): the unit direction of its stretch (S, d) and its half-length (S,), both in the
    standardised units (0: a point, as the paper's states)."""
    tangent = np.zeros_like(means, dtype=float)
    half = np.zeros(len(means))
    for s, n in zip(np.asarray(starts).tolist(), np.asarray(lengths).tolist()):
        if n < 3:
            continue
        a = np.asarray(means[s:s + n], dtype=float)
        u, v = a[1:-1] - a[:-2], a[2:] - a[1:-1]
        gu, gv = np.linalg.norm(u, axis=1), np.linalg.norm(v, axis=1)
        chord = a[2:] - a[:-2]
        gc = np.linalg.norm(chord, axis=1)
        cos = np.einsum("ij,ij->i", u, v) / np.maximum(gu * gv, 1e-300)
        h = np.maximum(STRETCH_SHARE * np.minimum(gu, gv) - STRETCH_FROM * sigma, 0.0)
        h = np.where((cos >= STRETCH_COS) & (gc > 0), h, 0.0)
        half[s + 1:s + n - 1] = h
        tangent[s + 1:s + n - 1] = np.where(h[:, None] > 0,
                                            chord / np.maximum(gc, 1e-300)[:, None], 0.0)
    return np.ascontiguousarray(tangent), half
