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
"""

from __future__ import annotations

import math
from bisect import bisect_left

import numpy as np

try:   # np.einsum without its Python wrapper (optimize=False calls exactly this)
    from numpy._core.multiarray import c_einsum as _einsum
except ImportError:  # numpy < 2
    try:
        from numpy.core.multiarray import c_einsum as _einsum
    except ImportError:
        _einsum = np.einsum

def window_sums(values: np.ndarray, n: int) -> np.ndarray:
    """``out[j] = sum(values[max(0, j - n + 1): j + 1])`` for a 1-D array."""
    cs = np.concatenate([[0.0], np.cumsum(values)])
    j = np.arange(values.size)
    return cs[j + 1] - cs[np.maximum(0, j - n + 1)]


def window_distances(live: np.ndarray, train: np.ndarray) -> np.ndarray:
    """Reference (brute force) distances of ``live`` (n, d) to every full training window:
    ``out[j]`` for window ends j = n-1 .. N-1, shape (N - n + 1,)."""
    n = live.shape[0]
    win = np.lib.stride_tricks.sliding_window_view(train, n, axis=0)  # (N-n+1, d, n)
    diff = win - live.T[None]
    return np.einsum("jdn,jdn->j", diff, diff)


E_DTYPE = np.float32


def augmented(train: np.ndarray) -> np.ndarray:
    """``[y, |y|^2, 1]^T`` (d + 2, N) of training vectors (N, d), in ``E_DTYPE``: what one
    matrix-vector product per step multiplies (shared by every reactor of a behaviour)."""
    y = np.asarray(train, dtype=float)
    return np.ascontiguousarray(np.vstack([y.T, np.einsum("jd,jd->j", y, y)[None],
                                           np.ones((1, y.shape[0]))]), dtype=E_DTYPE)


class SituationSearch:
    """Incremental distances of the live window to every training window (section 4.3.1).

    ``train``: (N, d) training vectors; ``valid``: (N,) bool, windows ending at j allowed.

    With ``E_k[j] = |x_k - y_j|^2`` (the newest live vector against every training vector) the
    window distance ``D_k[j] = sum_a E_{k-a}[j-a]`` advances along its diagonals:
    ``D_{k+1}[j] = D_k[j-1] + E_{k+1}[j] - E_{k+1-n}[j-n]``. Each step computes one ``E``, as
    one matrix-vector product ``[-2x, 1, |x|^2] . [y, |y|^2, 1]^T`` (N x (d+2)), keeps the last
    n + 1 of them in a ring (the one leaving the window is subtracted exactly as it was added),
    and shifts. No buffer is allocated after construction. Each diagonal restarts at j = 0, so
    rounding cannot build up over a long run (at most 2N additions per value).
    Measured at 24,000 training samples, d = 6, n = 40: the two matrix-vector products of the
    previous cross-correlation update cost ~200 us a step, this one ~40 us.

    ``E`` and the training side are single precision, the distances double: a step reads the
    (d + 2) x N training table and two ring rows, and with eight reactors the caches do not
    hold them between steps, so the bytes read decide the time (double precision: 0.5 ms a
    step at 24,000 samples in the interleaved benchmark). The distances stay within ~1e-6
    relative of the exact ones; the same inputs still give the same output to the last digit.

    The shift is an offset, not a copy: D lives in a buffer of 2N and each step moves its start
    back by one, so D[j - 1] already sits where D'[j] goes and the two sums are done in place
    (one N-value buffer in the cache instead of two); the best match is found right after the
    update, while D is still in the cache. Measured interleaved against the two-buffer shift
    (8 reactors, CPU time, loaded 2-core machine): 0.85-0.88x the tick with the coherence
    changes below, 0.81-0.83x with this too. Tried and slower: double-precision ring rows
    (one cast a step instead of two, but twice the bytes: 0.91x against 0.85x) and
    recomputing the leaving ``E`` from its stored query instead of keeping the ring (a second
    product a step: 0.93x). Every arithmetic step is the reference's, in the same order
    (tests/puppet_master/test_pm_fast_search.py checks the poses bit for bit).

    Searching several reactors at once does not pay (24,000 samples, 8 reactors, CPU time,
    loaded 2-core machine): one product of a behaviour's table with two reactors' stacked
    queries (sgemm) took 68 us against 2 x 36 us for two matrix-vector products, besides
    rounding unlike them; the sums of 8 reactors as one (8, N) array took 483 us against
    438 us one by one; the sums in cache-sized blocks of 2,048-8,192 were slower still; a
    compiled (numba) pass doing add, subtract and argmin at once gave 0.96x the search alone,
    for a 200 MB dependency. Without any situation update the 8-reactor tick took 0.41x
    its time: the rest is the generation step's Python.
    """

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray,
                 aug: np.ndarray | None = None, half_life: float = 0.0) -> None:
        y = np.asarray(train, dtype=float)
        self.n = n
        # weight of a sample ``age`` steps old: decay**age (1: the paper's uniform window)
        self.decay = 0.5 ** (1.0 / half_life) if half_life > 0 else 1.0
        self._lam_n = self.decay ** n
        N, d = y.shape
        self.d = d
        self.aug = augmented(y) if aug is None else aug
        ok = np.asarray(valid, dtype=bool)
        self.mask = np.where(ok, 0.0, np.inf)
        idx = np.flatnonzero(ok)
        # a contiguous run of allowed window ends (the usual case) is searched as a slice,
        # one pass over N fewer a step than adding the mask
        self.run = (int(idx[0]), int(idx[-1]) + 1) if idx.size and \
            idx.size == idx[-1] - idx[0] + 1 else None
        self.ring = np.zeros((n + 1, N), dtype=E_DTYPE)
        # per ring row: the product target, E[1:] (added) and E[:-n] (subtracted)
        self._rows = [(r, r[1:], r[:N - n] if N > n else r[:0]) for r in self.ring]
        self.k = n - 1
        self.N = N
        # the distances D live at _buf[o: o + N]; a step moves o back by one, so D[j - 1]
        # already sits where D'[j] goes and the update is in place (half the memory of two
        # buffers); when o reaches 0 the values move once to the end (every N steps)
        self._buf = np.zeros(2 * N)
        self._o = N
        self.dist = self._buf[N:]
        self._out = np.zeros(N)
        self._v = np.zeros((1, d + 2), dtype=E_DTYPE)
        self._v[0, d] = 1.0
        self._best: tuple[int, float] | None = None
        self._v1 = self._v[0]
        self._vx = self._v1[:d]

    def _query(self, x: np.ndarray, v: np.ndarray) -> None:
        np.multiply(x, -2.0, out=v[:self.d])
        v[self.d] = 1.0
        v[self.d + 1] = x.dot(x)

    def reset(self, window: np.ndarray) -> None:
        """Start from a live window (n, d), oldest first (exact computation, O(N n d))."""
        n = self.n
        window = np.asarray(window, dtype=float)
        for a in range(n):        # row by row, as push does: the same rounding, and no
            self._query(window[a], self._v[0])       # matrix-matrix product (a threaded
            np.matmul(self._v, self.aug, out=self.ring[a][None])   # BLAS took 50 ms here)
        self.k = n - 1
        self._best = None
        N = self.N
        self._buf[:] = 0.0
        self._o = N
        self.dist = dist = self._buf[N:]
        for a in range(min(n, N)):            # D[j] = sum_a decay^a E_{n-1-a}[j-a]
            dist[a:] += self.decay ** a * self.ring[n - 1 - a, :N - a]

    def push(self, x: np.ndarray) -> None:
        """Advance the live window by the newest vector ``x`` (d,)."""
        n, N = self.n, self.N
        self.k = k = self.k + 1
        new, new_tail, _ = self._rows[k % (n + 1)]
        old_head = self._rows[(k + 1) % (n + 1)][2]  # E of the vector leaving the window
        # the query as reset() makes it: -2x (exact in double) rounded to single on the store
        # (an expression and a cast assignment: 1.1 us against 2.8 us for np.multiply with a
        # single-precision out); np.dot of the 1-d query makes the same BLAS call (sgemv)
        # as np.matmul of the (1, d + 2) one, with less wrapping (1.0 us against 1.8 us)
        self._vx[...] = x * -2.0
        self._v1[self.d + 1] = x.dot(x)
        np.dot(self._v1, self.aug, out=new)
        o = self._o
        buf = self._buf
        if o == 0:
            buf[N:] = buf[:N]
            o = N
        d_prev = buf[o:o + N - 1]               # D[j - 1] is where D'[j] goes
        lam = self.decay
        if lam == 1.0:
            np.add(d_prev, new_tail, out=d_prev)
            if N > n:
                part = buf[o + n - 1:o + N - 1]
                np.subtract(part, old_head, out=part)
        else:                   # D' = lam D[j-1] + E_new - lam^n E_old (weights lam^age)
            np.multiply(d_prev, lam, out=d_prev)
            d_prev += new_tail
            if N > n:
                np.multiply(old_head, self._lam_n, out=self._out[n:])
                buf[o + n - 1:o + N - 1] -= self._out[n:]
        o -= 1
        buf[o] = new[0]
        self._o = o
        self.dist = buf[o:o + N]
        # the best match now, while the distances are still in the cache (the next step asks
        # for it after the other reactors' steps have passed through it)
        self._best = self._find_best()

    def distances(self) -> np.ndarray:
        """Current window distances to every training window end (inf where not allowed).
        The returned array is a reused buffer."""
        return np.add(self.dist, self.mask, out=self._out)

    def best(self) -> tuple[int, float]:
        """(training window end j, distance) of the best match; ties take the earliest j."""
        if self._best is None:
            self._best = self._find_best()
        return self._best

    def _find_best(self) -> tuple[int, float]:
        if self.run is not None:
            lo, hi = self.run
            o = self._o
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
    24,000; the distinct proposals cost ~30 us whatever the training length (CPU time,
    measured on a loaded 2-core machine). The distinct proposals are kept as a count of
    "bases" (source minus the step it was pushed at), so finding them costs the number of
    distinct ones, not n; with the allowed window ends one run, they are a bisection of the
    sorted bases. The proposed windows are copied whole from a strided view of the training
    vectors (an (m, n) index array cost ~16 us, this ~5 us) and their few costs are summed in
    plain Python with numpy's double arithmetic (13 us a step with best and push against
    22 us; 0.88x the 8-reactor tick).
    """

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray) -> None:
        self.y = np.ascontiguousarray(train, dtype=float)
        self.n = n
        self.valid = np.asarray(valid, dtype=bool)
        N, d = self.y.shape
        self.sy = window_sums(np.einsum("jd,jd->j", self.y, self.y), n)
        self._sy = self.sy.tolist()
        # every training window as a read-only view: windows[j - n + 1] is y[j - n + 1: j + 1]
        # (gathering the proposals from it copies whole windows, no (m, n) index array)
        self._windows = np.lib.stride_tricks.as_strided(
            self.y, shape=(max(N - n + 1, 0), n, d),
            strides=(self.y.strides[0], self.y.strides[0], self.y.strides[1]), writeable=False)
        self.buf = np.zeros((2 * n, d))
        self.i = n - 1
        self.sq = [0.0] * n              # |x|^2 of the live vectors in the ring
        self.sx = 0.0
        self._valid = self.valid.tolist()
        idx = np.flatnonzero(self.valid)
        # a contiguous run of allowed window ends (the usual case) is filtered by bisection
        self._run = (int(idx[0]), int(idx[-1]) + 1) if idx.size and \
            idx.size == idx[-1] - idx[0] + 1 else None
        # a source s pushed at step k0 proposes s + (k - k0) at step k: its "base" s - k0 is
        # fixed, so the distinct proposals are the distinct bases in the window plus k
        self._k = 0
        self._bases: list[int | None] = [None] * n
        self._count: dict[int, int] = {}

    def reset(self, window: np.ndarray) -> None:
        """Start from a live window (n, d), oldest first, with no known sources."""
        n = self.n
        self.buf[:n] = window
        self.buf[n:] = window
        sq = np.einsum("ad,ad->a", self.buf[:n], self.buf[:n])
        self.sq = sq.tolist()
        self.sx = float(sq.sum())
        self._bases = [None] * n
        self._count = {}
        self.i = n - 1

    def push(self, x: np.ndarray, source: int) -> None:
        """Add the newest live vector and the training index it was generated from."""
        n = self.n
        self.i = (self.i + 1) % n
        q = float(x.dot(x))
        self.sx += q - self.sq[self.i]
        self.buf[self.i] = x
        self.buf[self.i + n] = x
        self.sq[self.i] = q
        self._k += 1
        count = self._count
        gone = self._bases[self.i]
        if gone is not None:
            if count[gone] == 1:
                del count[gone]
            else:
                count[gone] -= 1
        base = source - self._k if source >= 0 else None
        self._bases[self.i] = base
        if base is not None:
            count[base] = count.get(base, 0) + 1

    def window(self) -> np.ndarray:
        """Live window (n, d), oldest first (a view)."""
        return self.buf[self.i + 1:self.i + 1 + self.n]

    def _proposed(self) -> list[int]:
        k = self._k
        if self._run is not None:
            bases = sorted(self._count)
            lo, hi = self._run
            return [b + k for b in bases[bisect_left(bases, lo - k):bisect_left(bases, hi - k)]]
        valid = self._valid
        size = len(valid)
        return sorted(b + k for b in self._count if 0 <= b + k < size and valid[b + k])

    def candidates(self) -> np.ndarray:
        """Sorted distinct allowed window ends proposed by the recent output's sources."""
        return np.array(self._proposed(), dtype=np.int64)

    def best(self) -> tuple[int, float]:
        """(training window end, distance) of the best candidate, or (-1, inf) if none; ties
        take the earliest window end."""
        proposed = self._proposed()
        if not proposed:
            return -1, math.inf
        back = self.n - 1
        w = self._windows[[c - back for c in proposed]]             # (m, n, d), small
        cross = _einsum("mnd,nd->m", w, self.window()).tolist()
        # costs sy - 2 cross in plain Python (a handful of values): the same double
        # arithmetic as numpy's, the first of equal costs wins as argmin does
        sy = self._sy
        best_c = proposed[0]
        best = sy[best_c] - 2.0 * cross[0]
        for c, x in zip(proposed[1:], cross[1:]):
            cost = sy[c] - 2.0 * x
            if cost < best:
                best_c, best = c, cost
        return best_c, max(best + self.sx, 0.0)


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
