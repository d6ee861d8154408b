"""BestMatch (paper section 4.3): situation similarity, generated-path coherence, balancing.

Window distances are sums over the last ``n`` samples of squared Euclidean distances between
live feature vectors and training feature vectors (features.py embeds and weights them).

Situation similarity scores every training window on every step without a Python loop and
without a per-step cost in ``n``: because the live window advances by one sample per step, the
window distances advance along their diagonals (:class:`SituationSearch`), one matrix-vector
product of the training vectors (N x d) per step.

Coherence compares the live window of the reactor's own features only against the training
windows its recent output came from (at most ``n`` candidates), so it costs O(n^2 d) whatever
the training length.

The sense of circling across consecutive matches (the lover on the slow paths, Python step;
the matched moment's sense: the sign of the demonstration's own 1 s orbit round its main
there, as fidelity.py measures the orbit). On the 18 slow paths of seeds 0-5 and 40-51 the
matched sense flips 2.47 times a second; along the demonstration itself 0.62. A third of the
steps jump (0.34 a step) and 14-16% of the jumps flip, in both searches: at 6.9-7.6% of the
situation choices and 4.1-4.7% of the coherence choices, most (491 of 918 over seeds 0-5,
40-45) where a coherence choice is followed by a situation one. They come where the two senses
look alike to the features: the situation features carry the reactor's speed, not its
velocity, so two moments at one place round the main, at one speed and look, circling in
opposite senses differ only by the window's relative positions (a 0.35 rad/s orbit at 0.12 m
moves the reactor 4 cm in the window); the lover faces its main throughout (facing 1.0
shown), so its look follows its place and tells nothing of the sense. Ahead of its main
(within 45 degrees of its look) the lover's matches flip 0.091 times a step, beside it
0.050-0.059, behind it 0.031-0.043; at a flip the new moment lies across the main's axis
from the last one in 31% of the flips (9% of all jumps). In the demonstration the sense goes
with the side: 81% negative on the main's left, 92% positive on its right.

Fewer flips do not bring the orbit back: the raw step's orbit stays at 0.32-0.35 rad/s
whatever the matched moments do. The lover on seeds 0-5 and 40-45 (walking main: raw step's
orbit; the matched moments' signed orbit averaged over 1 s of steps; flips a second): as
shipped 0.341 / 0.335 / 2.21. The reactor's own tangential speed round its main (m/s, signed,
over its spread) as one more situation column, weight 1: 0.350 / 0.348 / 1.56; as
tanh(speed / 0.03 m/s) (the sense alone): 0.340 / 0.360 / 1.94; averaged over 0.5 s: 0.328 /
0.325 / 2.43; the reactor's velocity in the main's frame instead of its speed, situation /
both searches: 0.333 / 0.330 / 2.16, - / 0.339 / 1.96; Params.ratio 0.5 / 2: 0.338 / 0.334 /
2.42, 0.338 / 0.334 / 1.90; Params.window 20 / 80: 0.318 / 0.318 / 1.97, 0.338 / 0.368 /
3.12. A heavy sense column lowers the generated orbit: the match then takes moments that
circle as slowly as the live reactor does. The lover's slow-path orbit (mean of 42 seeds,
demonstrated 0.457 rad/s): 0.345 as shipped; weight 0.25 / 0.5 / 1 / 2: 0.339 / 0.353 /
0.344 / 0.320; the sense alone 0.325. Met of 720 / 1440 / 1440 / 1440 on seeds 0-5 /
40-51 / 128-139 / 300-311 (the engine's alone), then the pursuit of 48 / 96 / 96 / 96
(bench-equivalent driver, Python step): as shipped 676 (8) / 1325 (35) / 1333 (24) / 1328
(26), 47 (1) / 85 (7) / 86 (6) / 84 (7); the column for every character, weight 1: 657 (14) /
1322 (33) / 1324 (29) / 1308 (34), 46 (0) / 92 (1) / 90 (3) / 87 (6) (the afraid character
gains chased and loses in the open: 123 / 244 / 233 / 227 -> 107 / 232 / 226 / 210); weight
0.5: 654 (15) / 1312 (33) / 1327 (25) / 1328 (24), 46 (0) / 84 (7) / 89 (5) / 87 (6); in both
searches, 0.5: 663 (15) / 1309 (35) / 1338 (20) / 1319 (24), 45 (1) / 85 (7) / 90 (4) / 87
(6). For the lover alone (its met of 144 / 288 / 288 / 288, the engine's alone; as shipped
129 (2) / 259 (6) / 260 (5) / 263 (9)): weight 0.25 131 (1) / 257 (10) / 264 (4) / 263 (8);
1: 132 (2) / 266 (7) / 271 (2) / 263 (13); 2: 128 (4) / 260 (11) / 266 (6) / 266 (8); both
searches, 1: 130 (3) / 258 (10) / 268 (4) / 270 (7); the sense alone 130 (1) / 261 (7) / 262
(4) / 264 (11). None kept: each raised the engine's misses on at least one set. The orbit is
lost between the matched moment and the raw step (step.py _trajectory), not in the match.

The lover's slow-path orbit meets its designer's (18 slow paths of seeds 0-5, 40-51: 0.333
against 0.326 rad/s, shown 0.457) by two errors cancelling; by the main's state at the 1 s
window's centre (still / walking): generated 0.189 / 0.369, its designer 0.088 / 0.401, shown
0.110 / 0.545. Beside a standing main (Python step) two thirds of the matched moments are
ones whose demonstrated main walked (the window's lag; shown they circle at 0.514; in seconds
still throughout the still cap holds the raw step to 0.139). In such seconds matched for four
fifths or more to moments whose main stood (14% of them) 1 s of those moments' own steps round
the main (u_tan) circles at 0.214 and the raw step at 0.275 (the main's carried step 0.004,
the drift correction 0.022), where the demonstration beside its standing main circles at
0.111: the re-matching keeps a sense the demonstration reverses. Lowering the standing part
lowers the figure further under its band; the walking part is the paths' (its designer 0.401
against 0.545). The stand cap after the smooth (step_detail.py) moves them 0.189 -> 0.213 and
0.369 -> 0.352. The own step round the main halved at moments whose main stood beside a
standing main (the lover alone, misses (the engine's) on seeds 0-5 / 40-51 against 15 (2) / 29
(6)): 0.189 -> 0.173, 17 (3) / 34 (7) (its still pace falls: fast and loops still/moving
under). Not kept.

Its sense held, in sign changes of the 1 s orbit a second beside a standing main (slow paths of
seeds 0-5, 40-45, Python step): generated 1.02, its designer 1.95, shown 1.64; orbit there 0.199
rad/s (designer 0.087). Three rules, the lover's misses (the engine's) on seeds 0-5 / 40-51 /
128-139 against 15 (2) / 28 (5) / 27 (5): the steps since its sense last changed (the 0.5 s
sum of its own angular steps round the main, at most the shown runs' 99th percentile) as a
situation and coherence column at weight 0.5 over its spread (as features.since_push): flips
0.66, orbit 0.181, 13 (1) / 32 (11) / 24 (5) (the match then takes moments deep in long runs,
most beside a walking main); the coherence candidate (the shown moments in their order) taken
whenever the live main stands: flips 1.09, orbit 0.160 (walking 0.368 -> 0.384), 11 (0) / 27
(10) / 28 (6); only at moments whose shown main stood: flips 0.43, orbit 0.202, 15 (4) / 30
(9) / 28 (6). None kept. The second lowers the standing part as meant, but its slow orbit
misses (the engine's) go 3 -> 6: the figure sits under its band once the walking part (0.368,
shown 0.545) is no longer lifted by the standing one; over three runs (relative_motion x 1,
1 +- 0.001) the engine's alone 1 / 27 / 20 against 5 / 16 / 13.

The stalker's orbit beside a turning main (loops and slow paths of seeds 40-51 and 128-139,
Python step; steps whose main walks over 0.05 m/s and turns its walking direction over 0.5
rad/s in 0.5 s, within 0.6 m). On the loops the matched moments orbit their main at 0.647-0.678
rad/s (1 s, absolute), as the demonstration's own turning moments (0.678), but along the live
main's turn only 0.386-0.398 (the live reactor 0.509-0.521): their demonstrated mains turned
the other way on 58-59% of the steps (the features, in the main's frame, do not tell a left
turn from a right one; shown, the orbit goes with the main's turn on 59% of its turning
samples). The best window among moments orbiting at 0.6 rad/s or more costs 1.01-1.02 x the
best (median; slow paths 1.16-1.18) and loses on the velocities (main 73-79 against 62-66 of
about 165, reactor 35 against 29) and the still state, not on the relative position: the live
loops main walks at 0.229 m/s where it turns over 1.5 rad/s, the demonstrated main at 0.104
there and 0.142 in its straight walks, so the velocity picks the straight walks. Re-weighed for
the stalker alone (misses (the engine's) on seeds 0-5 / 40-51 / 128-139 against 5 (2) / 29 (14)
/ 12 (6), at relative_motion x 1 +- 0.001 5 (2) / 29 (14) / 11 (5) and 6 (2) / 27 (13) / 12
(7); orbit slow / fast / loops 0.551 / 0.611 / 0.594 rad/s, its designer 0.576 / 0.728 / 0.682,
shown 0.633): Params.w_velocity 0.7 15 (7) / 27 (14) / 16 (7), 0.553 / 0.626 / 0.628; 0.5 13
(4) / 34 (17) / 22 (10), 0.555 / 0.638 / 0.654; the main's velocity alone x 0.7 9 (5) / 24 (12)
/ 12 (5), 0.541 / 0.617 / 0.604; x 0.5 11 (6) / 33 (16) / 18 (10); the main's speed compared as
itself up to the shown main's 90th percentile walk (0.22 m/s) and as that above it 7 (3) / 27
(12) / 18 (9), 0.556 / 0.628 / 0.609; above the median walk (0.12 m/s) at half its excess 11
(5) / 28 (13) / 16 (7), 0.548 / 0.640 / 0.618; Params.w_rel_position 1.25 11 (4) / 34 (19) / 18
(8), 0.555 / 0.628 / 0.617; 1.5 12 (3) / 28 (14) / 22 (13), 0.564 / 0.646 / 0.637; with the
still state x 1.5 10 (5) / 30 (16) / 15 (8), 0.563 / 0.648 / 0.623; Params.ratio 2 / 0.5 8 (4)
/ 26 (13) / 16 (10), 8 (4) / 32 (18) / 18 (11) (loops 0.594 / 0.589). As more columns (weight
over their spread): the main's delta direction (cos, sin) in the coherence vectors 6 (2) / 27
(13) / 14 (8), loops 0.599; in the situation vectors 12 (5) / 25 (11) / 14 (9), 0.565 / 0.616 /
0.595; the reactor's own angular rate round its main (per step, within 4 rad/s) in the
situation vectors 9 (5) / 28 (13) / 11 (5), 0.554 / 0.609 / 0.588; its 0.25 s mean 9 (4) / 30
(14) / 14 (8), at 0.5 8 (4) / 30 (14) / 14 (7), in the coherence vectors 7 (3) / 31 (13) / 14
(9) (loops 0.585-0.591). Every weighting that lifts the orbit takes moments whose main walked
slower, and the still/moving, speed and contact misses rise with it. None kept.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from behaviors.puppet_master import search_kernel


def window_sums(values: np.ndarray, n: int) -> np.ndarray:
    """``out[j] = sum(values[max(0, j - n + 1): j + 1])`` for a 1-D array."""
    cs = np.concatenate([[0.0], np.cumsum(values)])
    j = np.arange(values.size)
    return cs[j + 1] - cs[np.maximum(0, j - n + 1)]


E_DTYPE = np.float32
NOT_FOUND = -2      # SituationSearch's best window end before it is looked for


def augmented(train: np.ndarray, gate_from: int | None = None) -> np.ndarray:
    """``[y, |y|^2, 1]^T`` (d + 2, N) of training vectors (N, d), in ``E_DTYPE`` (shared by
    every reactor of a behaviour); with columns gated from ``gate_from`` on
    (:class:`SituationSearch`), ``[y, |y_<g|^2, |y_>=g|^2]^T``."""
    y = np.asarray(train, dtype=float)
    if gate_from is None or gate_from >= y.shape[1]:
        tail = [np.einsum("jd,jd->j", y, y)[None], np.ones((1, y.shape[0]))]
    else:
        a, b = y[:, :gate_from], y[:, gate_from:]
        tail = [np.einsum("jd,jd->j", a, a)[None], np.einsum("jd,jd->j", b, b)[None]]
    return np.ascontiguousarray(np.vstack([y.T, *tail]), dtype=E_DTYPE)


class SituationSearch:
    """Incremental distances of the live window to every training window (section 4.3.1).

    ``train``: (N, d) training vectors; ``valid``: (N,) bool, windows ending at j allowed.

    With ``E_k[j] = |x_k - y_j|^2`` (the newest live vector against every training vector) the
    window distance ``D_k[j] = sum_a E_{k-a}[j-a]`` advances along its diagonals:
    ``D_{k+1}[j] = D_k[j-1] + E_{k+1}[j] - E_{k+1-n}[j-n]``. Each step computes the new ``E``
    and again the one leaving the window (from its stored query: the same arithmetic, so it
    is subtracted exactly as it was added) and updates D, in one compiled pass over the
    training table (search_kernel.situation_push). No buffer is allocated after construction.
    Each diagonal restarts at j = 0, so rounding cannot build up over a long run (at most 2N
    additions per value).

    ``E`` and the training side are single precision, the distances double: with eight
    reactors the caches do not hold the tables between steps, so the bytes read decide the
    time. The distances stay within ~1e-6 relative of the exact ones; the same inputs give
    the same output to the last digit.

    The shift is an offset, not a copy: D lives in a buffer of 2N and each step moves its start
    back by one, so D[j - 1] already sits where D'[j] goes and the sums are done in place.

    Measured interleaved against the numpy version it replaces (one single-precision BLAS
    matrix-vector product ``[-2x, 1, |x|^2] . [y, |y|^2, 1]^T`` a step into a ring of the last
    n + 1 ``E`` rows, then an add, a subtract and an argmin over D), 8 searches on 4 tables,
    thread CPU time, loaded 2-core machine: 0.81x at 24,000 samples, 0.44x at 3,200. That
    pass wrote and read a 4-byte row of N per step and held 41 of them per reactor (3.9 MB at
    24,000); the compiled pass recomputes the leaving ``E`` from training rows it read n
    samples before (still in L1) and finds the best block by block while D is in L1. The
    earlier attempts at compiling it were slower than the BLAS product because the best-so-far
    test inside the loop kept the loop from running in vector lanes.

    Searching several reactors at once did not pay (24,000 samples, 8 reactors): one product
    of a behaviour's table with two reactors' stacked queries took 68 us against 2 x 36 us for
    two matrix-vector products, and the sums of 8 reactors as one (8, N) array 483 us against
    438 us one by one.
    """

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray,
                 aug: np.ndarray | None = None, half_life: float = 0.0,
                 gate: tuple[int, Callable[[np.ndarray], float]] | None = None) -> None:
        y = np.asarray(train, dtype=float)
        self.n = n
        # (first gated column, the live vector's gate): those columns' part of each live
        # sample's distance weighed by its gate (features.room_gate); (d, None): none
        self.gate_from, self.gate = gate if gate is not None else (y.shape[1], None)
        # weight of a sample ``age`` steps old: decay**age (1: the paper's uniform window)
        self.decay = 0.5 ** (1.0 / half_life) if half_life > 0 else 1.0
        self._lam_n = self.decay ** n
        N, d = y.shape
        self.d = d
        self.aug = augmented(y, self.gate_from) if aug is None else aug
        ok = np.asarray(valid, dtype=bool)
        self.mask = np.where(ok, 0.0, np.inf)
        idx = np.flatnonzero(ok)
        # a contiguous run of allowed window ends (the usual case) is searched in the pass
        self.run = (int(idx[0]), int(idx[-1]) + 1) if idx.size and \
            idx.size == idx[-1] - idx[0] + 1 else None
        self._lo, self._hi = self.run if self.run is not None else (0, 0)
        # -2x and |x|^2 of the last n + 1 live vectors, by step number mod n + 1
        self._queries = np.zeros((n + 1, d), dtype=E_DTYPE)
        self._norms = np.zeros(n + 1, dtype=E_DTYPE)
        self._gates = np.ones(n + 1, dtype=E_DTYPE)
        self.N = N
        # the distances D live at _buf[o: o + N]; a step moves o back by one, so D[j - 1]
        # already sits where D'[j] goes and the update is in place (half the memory of two
        # buffers); when o reaches 0 the values move once to the end (every N steps)
        self._buf = np.zeros(2 * N)
        # the state a push changes and its constants, as arrays (match_step_kernel pushes
        # from a compiled step): o, the steps pushed k, the best window end (NOT_FOUND: not
        # looked for since the reset), lo, hi, the first gated column, n; the best distance,
        # the recency weight and its n-th power
        self._at = np.array([N, n - 1, NOT_FOUND, self._lo, self._hi, self.gate_from, n],
                            dtype=np.int64)
        self._sf = np.array([np.inf, self.decay, self._lam_n])
        self._out = np.zeros(N)
        self._e = np.zeros(N, dtype=E_DTYPE)
        self._e_new = np.zeros(search_kernel.BLOCK, dtype=E_DTYPE)
        self._e_old = np.zeros(search_kernel.BLOCK, dtype=E_DTYPE)

    @property
    def k(self) -> int:
        """Live vectors pushed since the reset, plus n - 1."""
        return int(self._at[1])

    @property
    def dist(self) -> np.ndarray:
        """The window distances (N,) (a view of the buffer, moved by each push)."""
        o = int(self._at[0])
        return self._buf[o:o + self.N]

    def reset(self, window: np.ndarray) -> None:
        """Start from a live window (n, d), oldest first (exact computation, O(N n d))."""
        window = np.ascontiguousarray(window, dtype=float)
        N = self.N
        self._buf[:] = 0.0
        self._at[0], self._at[1], self._at[2] = N, self.n - 1, NOT_FOUND
        gates = np.array([self._gate(x) for x in window])
        search_kernel.situation_reset(self.aug, self.dist, self.n, self._queries,
                                      self._norms, window, self.decay, self._e, self._gates,
                                      gates, self.gate_from)

    def push(self, x: np.ndarray) -> None:
        """Advance the live window by the newest vector ``x`` (d,)."""
        at = self._at
        k = int(at[1]) + 1
        o, j, least = search_kernel.situation_push(
            self.aug, self._buf, int(at[0]), self.n, self._queries, self._norms, k, x,
            self.decay, self._lam_n, self._lo, self._hi, self._e_new, self._e_old,
            self._gates, self._gate(x), self.gate_from)
        at[0], at[1] = o, k
        # the best match found in the same pass, while the distances were in the cache
        if self.run is not None:
            at[2], self._sf[0] = j, max(least, 0.0)
        else:
            at[2], self._sf[0] = self._find_best()

    def _gate(self, x: np.ndarray) -> float:
        return 1.0 if self.gate is None else self.gate(x)

    def arrays(self) -> tuple[np.ndarray, ...]:
        """The search's table and state as match_step_kernel.match_step takes them."""
        return (self.aug, self._buf, self._at, self._sf, self._queries, self._norms,
                self._gates, self._e_new, self._e_old)

    def distances(self) -> np.ndarray:
        """Current window distances to every training window end (inf where not allowed).
        The returned array is a reused buffer."""
        return np.add(self.dist, self.mask, out=self._out)

    def best(self) -> tuple[int, float]:
        """(training window end j, distance) of the best match; ties take the earliest j."""
        if self._at[2] == NOT_FOUND:
            self._at[2], self._sf[0] = self._find_best()
        return int(self._at[2]), float(self._sf[0])

    def _find_best(self) -> tuple[int, float]:
        if self.run is not None:
            lo, hi = self.run
            o = int(self._at[0])
            buf = self._buf
            j = lo + int(buf[o + lo:o + hi].argmin())
            return j, max(float(buf[o + j]), 0.0)
        d = self.distances()
        j = int(d.argmin())
        return j, max(float(d[j]), 0.0)


class CoherenceSearch:
    """Generated-path coherence (section 4.3.2) over the sources of the recent output.

    The output sample generated ``age`` steps ago came from training index ``source``; now it
    proposes the training window ending at ``source + age``. ``valid``: (N,) bool.

    The n recent sources propose few distinct windows (a run of consecutive sources proposes
    one), so only the distinct ones are scored: ``|x|^2 + |y_c|^2 - 2 x . y_c`` summed over
    the window, with the window sums of ``|y|^2`` precomputed. Scoring all n proposals
    (duplicates included) cost ~100-130 us a step; keeping every training window's distance
    up to date as the situation search does cost ~75 us at 3,200 samples but ~160 us at
    24,000 (CPU time, measured on a loaded 2-core machine). A source s pushed at step k0
    proposes s + (k - k0) at step k: its "base" s - k0 is fixed, so the distinct proposals
    are the distinct bases in the window plus k. Finding and scoring them is compiled
    (search_kernel.coherence_best): in Python and numpy (a dict of bases, a gather of the
    proposed windows, the costs in plain Python) it took 13-19 us a step hot and far more
    with eight reactors sharing the caches.

    What it does to a demonstrated event (the playful friend's dart, 0.6 s from 0.17 m to a
    touch), traced on seed 8's slow path (Python step): after a step generated from a dart's
    run-up the next step goes on with it in 61% of the steps (the best candidate here is its
    continuation in 72%, but the balancer leaves half of the steps to situation, which jumps),
    so a match stays on a dart 1-3 steps and the friend's darts stop 0.08-0.11 m short.
    Proposing only the newest source's continuation (Python step, seeds 0-5 / 8-13 / 26-31):
    the friend's misses 1 / 6 / 4 -> 9 / 7 / 7, its contact lower still (seed 0 0.009-0.012
    against at least 0.021): the contact it has comes from the jumps. Not used.
    """

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray) -> None:
        self.y = np.ascontiguousarray(train, dtype=float)
        self.n = n
        self.valid = np.ascontiguousarray(valid, dtype=bool)
        self.sy = window_sums(np.einsum("jd,jd->j", self.y, self.y), n)
        self.buf = np.zeros((2 * n, self.y.shape[1]))
        self.sq = np.zeros(n)            # |x|^2 of the live vectors in the ring
        self._sx = np.zeros(1)           # their sum
        self._ik = np.array([n - 1, 0])  # the ring slot of the newest, the steps pushed
        # per ring slot: the base of its live vector (search_kernel.NO_SOURCE: none)
        self._bases = np.full(n, search_kernel.NO_SOURCE, dtype=np.int64)

    @property
    def i(self) -> int:
        """Ring slot of the newest live vector."""
        return int(self._ik[0])

    @property
    def sx(self) -> float:
        """Sum of |x|^2 over the live window."""
        return float(self._sx[0])

    def reset(self, window: np.ndarray) -> None:
        """Start from a live window (n, d), oldest first, with no known sources."""
        n = self.n
        self.buf[:n] = window
        self.buf[n:] = window
        self.sq[:] = np.einsum("ad,ad->a", self.buf[:n], self.buf[:n])
        self._sx[0] = float(self.sq.sum())
        self._bases[:] = search_kernel.NO_SOURCE
        self._ik[0] = n - 1

    def push(self, x: np.ndarray, source: int) -> None:
        """Add the newest live vector (d,) and the training index it was generated from."""
        search_kernel.coherence_push(self.buf, self.sq, self._bases, self._sx, self._ik, x,
                                     source)

    def arrays(self) -> tuple[np.ndarray, ...]:
        """The search's table and state as match_step_kernel.match_step takes them."""
        return (self.y, self.buf, self.sq, self._bases, self._sx, self._ik, self.valid,
                self.sy)

    def window(self) -> np.ndarray:
        """Live window (n, d), oldest first (a view)."""
        return self.buf[self.i + 1:self.i + 1 + self.n]

    def candidates(self) -> np.ndarray:
        """Sorted distinct allowed window ends proposed by the recent output's sources."""
        ends = np.unique(self._bases[self._bases != search_kernel.NO_SOURCE]) + self._ik[1]
        ends = ends[(ends >= self.n - 1) & (ends < self.valid.size)]
        return ends[self.valid[ends]].astype(np.int64)

    def best(self) -> tuple[int, float]:
        """(training window end, distance) of the best candidate, or (-1, inf) if none; ties
        take the earliest window end."""
        return search_kernel.coherence_best(self.y, self.buf, self._bases, self._ik,
                                            self.valid, self.sy, self._sx)


class Balancer:
    """Similarity balancing (section 4.3.3): a dynamic weight k on the coherence cost.

    Coherence wins a step when ``k * coherence < situation``. After each step where both were
    available, ``log k += gain * (chose_coherence - target_share)`` with ``target_share =
    1 / (1 + ratio)`` for a situation:coherence ``ratio``. Summed, this is
    ``log k = gain * steps * (running share of coherence choices - target_share)``: k follows the
    running share, rising while coherence is chosen more than its share. As an integral
    controller it keeps ``log k`` bounded only while the share sits at the target, so over a
    run the choices follow the ratio (the colour-histogram matching of Kopf et al. works the
    same way). The metric with the better weighted score still decides every step; nothing
    alternates by force. A coherence loop makes its cost shrink, which raises k until
    situation takes over. ``gain`` 0.1 moves k by a factor e in 20 one-sided steps (half a
    second at 40 Hz). Driving k from a smoothed share instead (an average over 200 steps)
    lagged and oscillated: measured 8-second coherence runs and 10-second shares swinging
    0.17-0.71, against at most 3 seconds and 0.33-0.59 this way.
    ``share`` is a running share over about ``window`` steps, for display.

    Where the playful friend's darts fall short (seeds 0-5, loops / slow paths, Python step):
    the match stays on a moment under 0.09 m from its main 4.4 samples at a time (the
    demonstration 10), and 67 / 62% of its exits jump where the demonstration stays near,
    half of them by the coherence search; there the live friend is 3.2 / 2.6 cm farther out
    than the moment it leaves (1.0-1.5 cm ten steps before the dart), so both searches take
    moments farther out. The lag is the world place's cap (step.py).
    """

    def __init__(self, ratio: float = 1.0, gain: float = 0.1, window: int = 200,
                 log_k_limit: float = 30.0) -> None:
        self.target_share = 1.0 / (1.0 + ratio)
        self.gain = gain
        self.window = window
        self.log_k_limit = log_k_limit
        self.log_k = 0.0
        self.share = self.target_share
        self.choices = 0
        self.coherence_choices = 0

    @property
    def k(self) -> float:
        """Current weight on the coherence cost."""
        return math.exp(self.log_k)

    def choose(self, situation_cost: float, coherence_cost: float) -> bool:
        """True to take the coherence candidate this step; updates k and the shares."""
        if not math.isfinite(coherence_cost):
            return False
        use = math.exp(self.log_k) * coherence_cost < situation_cost
        chosen = 1.0 if use else 0.0
        log_k = self.log_k + self.gain * (chosen - self.target_share)
        limit = self.log_k_limit
        self.log_k = min(max(log_k, -limit), limit)
        self.choices = choices = self.choices + 1
        self.coherence_choices += int(use)
        alpha = max(1.0 / choices, 1.0 / self.window)
        self.share += alpha * (chosen - self.share)
        return use
