"""Reference BestMatch searches: the plain formulation the fast searches of
behaviors/puppet_master/similarity.py must reproduce to the last bit.

The situation search keeps two distance buffers and a ring of E rows and shifts one buffer into
the other every step; the coherence search scores every distinct proposal with numpy from an
(m, n) index array. Both do the same floating-point operations in the same order as the
compiled ones (search_kernel.py), so any difference in a search's choice or cost, and so in a
generated pose, is a fault of the fast path.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.puppet_master.similarity import augmented, window_sums


class ReferenceSituationSearch:
    """Situation similarity: ``D'[j] = (lam D[j-1] + E_new[j]) - lam^n E_old[j-n]`` into a
    second buffer, with a ring of the last n + 1 E rows; E in single precision as
    ``(|x|^2 + |y|^2) + sum_c (-2 x_c) y_c`` (terms in that order), D in double."""

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray,
                 aug: np.ndarray | None = None, half_life: float = 0.0,
                 gate=None) -> None:
        y = np.asarray(train, dtype=float)
        self.n, (N, self.d) = n, y.shape
        self.decay = 0.5 ** (1.0 / half_life) if half_life > 0 else 1.0
        # columns from g0 on weighed by each live vector's gate: (g0, gate(x)) or none
        self.g0, self.gate = gate if gate is not None else (self.d, None)
        self.aug = augmented(y, self.g0) if aug is None else aug
        self.mask = np.where(np.asarray(valid, dtype=bool), 0.0, np.inf)
        self.ring = np.zeros((n + 1, N), dtype=self.aug.dtype)
        self.k = n - 1
        self.dist = np.zeros(N)

    def _e(self, x: np.ndarray, out: np.ndarray) -> None:
        f = self.aug.dtype.type
        x = np.asarray(x, dtype=float)
        g0 = self.g0
        q = (x * -2.0).astype(self.aug.dtype)
        xx = 0.0
        for v in x[:g0].tolist():
            xx += v * v
        if g0 < self.d:
            g = self.gate(x)
            q[g0:] = (x[g0:] * (-2.0 * g)).astype(self.aug.dtype)
            xr = 0.0
            for v in x[g0:].tolist():
                xr += v * v
            xx += g * xr
            out[:] = f(xx) + (self.aug[self.d] + f(g) * self.aug[self.d + 1])
        else:
            out[:] = f(xx) + self.aug[self.d]
        for c in range(self.d):
            out += q[c] * self.aug[c]

    def reset(self, window: np.ndarray) -> None:
        n, N = self.n, self.dist.size
        for a in range(n):
            self._e(np.asarray(window[a], dtype=float), self.ring[a])
        self.k = n - 1
        self.dist = np.zeros(N)
        w = 1.0
        for a in range(min(n, N)):
            self.dist[a:] += w * self.ring[n - 1 - a, :N - a].astype(float)
            w *= self.decay

    def push(self, x: np.ndarray) -> None:
        n = self.n
        self.k += 1
        new = self.ring[self.k % (n + 1)]
        old = self.ring[(self.k + 1) % (n + 1)]
        self._e(x, new)
        d, d2 = self.dist, np.empty_like(self.dist)
        d2[0] = new[0]
        d2[1:] = d[:-1] * self.decay + new[1:]
        if d2.size > n:
            d2[n:] = d2[n:] - old[:-n].astype(float) * self.decay ** n
        self.dist = d2

    def distances(self) -> np.ndarray:
        return self.dist + self.mask

    def best(self) -> tuple[int, float]:
        d = self.distances()
        j = int(d.argmin())
        return j, max(float(d[j]), 0.0)


class ReferenceCoherenceSearch:
    """Coherence: every source proposes ``source + age``; the distinct allowed proposals are
    scored ``sum |y|^2 - 2 x . y`` (+ ``sum |x|^2``) with numpy from an (m, n) index array."""

    def __init__(self, train: np.ndarray, n: int, valid: np.ndarray) -> None:
        self.y = np.ascontiguousarray(train, dtype=float)
        self.n = n
        self.valid = np.asarray(valid, dtype=bool)
        self.sy = window_sums(np.einsum("jd,jd->j", self.y, self.y), n)
        self.live: list[np.ndarray] = []
        self.src: list[int] = []

    def reset(self, window: np.ndarray) -> None:
        self.live = [np.array(w, dtype=float) for w in window]
        self.src = [-1] * self.n
        self.sq = list(np.einsum("ad,ad->a", np.array(self.live), np.array(self.live)))
        self.sx = float(np.sum(self.sq))

    def push(self, x: np.ndarray, source: int) -> None:
        """|x|^2 (summed term by term) of the window is kept as a running sum (the newest
        in, the oldest out)."""
        q = 0.0
        for v in np.asarray(x, dtype=float).tolist():
            q += v * v
        self.sx += q - self.sq[0]
        self.sq = self.sq[1:] + [q]
        self.live = self.live[1:] + [np.array(x, dtype=float)]
        self.src = self.src[1:] + [source]

    def best(self) -> tuple[int, float]:
        n = self.n
        src = np.array(self.src)
        cand = src + np.arange(n - 1, -1, -1)
        cand = cand[(src >= 0) & (cand < self.valid.size)]
        cand = np.unique(cand[self.valid[cand]])
        if cand.size == 0:
            return -1, math.inf
        window = np.array(self.live)
        w = self.y[cand[:, None] + np.arange(-n + 1, 1)[None, :]]
        # the cross terms summed one at a time, window sample by sample (cumsum is sequential)
        cross = np.cumsum((w * window[None]).reshape(cand.size, -1), axis=1)[:, -1]
        costs = self.sy[cand] - 2.0 * cross
        k = int(costs.argmin())
        return int(cand[k]), max(float(costs[k]) + self.sx, 0.0)
