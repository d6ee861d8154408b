"""BestMatch (paper section 4.3): situation similarity, generated-path coherence, balancing.

Window distances are sums over the last ``n`` samples of squared Euclidean distances between
live feature vectors and training feature vectors (features.py embeds and weights them).

Situation similarity scores every training window on every step without a Python loop and
without a per-step cost in ``n``: the distance of the live window ending now to the training
window ending at j is ``Sx + Sy[j] - 2 C[j]`` with ``C[j] = sum_a x[now-a] . y[j-a]``. Because
the live window advances by one sample per step, ``C`` advances along its diagonals:
``C'[j] = C[j-1] + x[now] . y[j] - x[now-n] . y[j-n]``, two matrix-vector products of the
training vectors (N x d) per step. Each diagonal restarts exactly at j = 0 and ends at N - 1, so
rounding error cannot build up over a long run (at most N additions, ~1e-12 relative).

Coherence compares the live window of the reactor's own features only against the training
windows its recent output came from (at most ``n`` candidates), so it costs O(n^2 d) whatever
the training length.
"""

from __future__ import annotations

import math

import numpy as np


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


class SituationSearch:
    """Incremental distances of the live window to every training window (section 4.3.1).

    ``train``: (N, d) training vectors; ``valid``: (N,) bool, windows ending at j allowed.
    """

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray) -> None:
        self.y = np.ascontiguousarray(train, dtype=float)
        self.n = n
        N, d = self.y.shape
        sy = window_sums(np.einsum("jd,jd->j", self.y, self.y), n)
        self.base = np.where(valid, sy, np.inf)
        self.c = np.zeros(N)
        self._c2 = np.zeros(N)
        self._p_now = np.zeros(N)
        self._p_old = np.zeros(N)
        self._d = np.zeros(N)
        self.hist = np.zeros((n, d))
        self.head = 0
        self.sx = 0.0

    def reset(self, window: np.ndarray) -> None:
        """Start from a live window (n, d), oldest first (exact computation, O(N n d))."""
        n = self.n
        self.hist[:] = window
        self.head = 0
        p = self.y @ window.T  # (N, n)
        self.c[:] = 0.0
        N = self.y.shape[0]
        for a in range(min(n, N)):
            self.c[a:] += p[:N - a, n - 1 - a]
        self.sx = float(np.dot(self.hist.ravel(), self.hist.ravel()))

    def push(self, x: np.ndarray) -> None:
        """Advance the live window by the newest vector ``x`` (d,)."""
        n = self.n
        old = self.hist[self.head]
        np.dot(self.y, old, out=self._p_old)
        np.dot(self.y, x, out=self._p_now)
        c, c2 = self.c, self._c2
        c2[0] = self._p_now[0]
        np.add(c[:-1], self._p_now[1:], out=c2[1:])
        if c2.size > n:
            np.subtract(c2[n:], self._p_old[:-n], out=c2[n:])
        self.c, self._c2 = c2, c
        self.hist[self.head] = x
        self.head = (self.head + 1) % n
        flat = self.hist.ravel()
        self.sx = float(np.dot(flat, flat))

    def distances(self) -> np.ndarray:
        """Current window distances to every training window end (inf where not allowed).
        The returned array is a reused buffer."""
        np.multiply(self.c, -2.0, out=self._d)
        self._d += self.base
        self._d += self.sx
        return self._d

    def best(self) -> tuple[int, float]:
        """(training window end j, distance) of the best match; ties take the earliest j."""
        d = self.distances()
        j = int(np.argmin(d))
        return j, max(float(d[j]), 0.0)


class CoherenceSearch:
    """Generated-path coherence (section 4.3.2) over the sources of the recent output.

    The output sample generated ``age`` steps ago came from training index ``source``; now it
    proposes the training window ending at ``source + age``. ``valid``: (N,) bool.
    """

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray) -> None:
        self.y = np.ascontiguousarray(train, dtype=float)
        self.n = n
        self.valid = np.asarray(valid, dtype=bool)
        d = self.y.shape[1]
        self.buf = np.zeros((2 * n, d))
        self.src = np.full(2 * n, -1, dtype=np.int64)
        self.i = n - 1
        self.ages = np.arange(n - 1, -1, -1, dtype=np.int64)
        self.offsets = np.arange(-n + 1, 1, dtype=np.int64)

    def reset(self, window: np.ndarray) -> None:
        """Start from a live window (n, d), oldest first, with no known sources."""
        n = self.n
        self.buf[:n] = window
        self.buf[n:] = window
        self.src[:] = -1
        self.i = n - 1

    def push(self, x: np.ndarray, source: int) -> None:
        """Add the newest live vector and the training index it was generated from."""
        n = self.n
        self.i = (self.i + 1) % n
        self.buf[self.i] = x
        self.buf[self.i + n] = x
        self.src[self.i] = source
        self.src[self.i + n] = source

    def window(self) -> np.ndarray:
        """Live window (n, d), oldest first (a view)."""
        return self.buf[self.i + 1:self.i + 1 + self.n]

    def candidates(self) -> np.ndarray:
        """Sorted distinct allowed window ends proposed by the recent output's sources."""
        src = self.src[self.i + 1:self.i + 1 + self.n]
        cand = src + self.ages
        cand = cand[(src >= 0) & (cand < self.valid.size)]
        cand = cand[self.valid[cand]]
        return np.unique(cand)

    def best(self) -> tuple[int, float]:
        """(training window end, distance) of the best candidate, or (-1, inf) if none."""
        cand = self.candidates()
        if cand.size == 0:
            return -1, math.inf
        diff = self.y[cand[:, None] + self.offsets[None, :]] - self.window()[None]
        costs = np.einsum("mnd,mnd->m", diff, diff)
        k = int(np.argmin(costs))
        return int(cand[k]), float(costs[k])


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
        use = self.k * coherence_cost < situation_cost
        self.log_k += self.gain * ((1.0 if use else 0.0) - self.target_share)
        self.log_k = min(max(self.log_k, -self.log_k_limit), self.log_k_limit)
        self.choices += 1
        self.coherence_choices += int(use)
        alpha = max(1.0 / self.choices, 1.0 / self.window)
        self.share += alpha * ((1.0 if use else 0.0) - self.share)
        return use
