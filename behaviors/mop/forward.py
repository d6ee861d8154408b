"""The forward algorithm on a sliding window (MOP section 3.2.2, equations 2-7), for many templates.

Every template keeps a window of ``2p + 1`` states around its progress mean (equation 7, with
``i_inf = N - 2p`` near the end; a template shorter than the window is followed whole). Each step
the windowed distribution is moved by the transitions, renormalised (equation 6's ``k``),
multiplied by the Gaussian observation probabilities and renormalised again; the logarithm of
that normaliser is the step's log-likelihood (equation 2 kept as a running sum of logs, so runs
of any length stay finite). Progress is the mean state (equation 3), its spread the variance
(equation 4). Everything is computed in the log domain for every template at once.

Besides the main window, each template keeps a second window on its first states fed by the
restart probability: when that window holds more probability than the main one, a new
performance has begun and it becomes the main window (re-entry).
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.mop.hmm import TemplateBank, Transitions

_TINY = 1e-300


class WindowedForward:
    """Windowed forward algorithm over every template of a bank at once (stateful).

    ``sigma``: observation standard deviation in standardised feature units; ``half_window``: p,
    in states; ``floor``: probability added to each main-window state per step so a follower can
    recover after the input left the template. ``step(z)`` takes one standardised sample (d,).
    """

    def __init__(self, bank: TemplateBank, sigma: float = 0.2, half_window: int = 15,
                 transitions: Transitions = Transitions(), floor: float = 1e-8) -> None:
        if not (sigma > 0 and math.isfinite(sigma)):
            raise ValueError(f"sigma must be a positive number, got {sigma}")
        if int(half_window) < 1:
            raise ValueError(f"half_window must be at least 1 state, got {half_window}")
        self.bank = bank
        self.sigma = float(sigma)
        self.half_window = int(half_window)
        self.transitions = transitions
        self.floor = float(floor)
        k = len(bank.names)
        lengths = bank.lengths
        self._k = k
        wk = np.minimum(2 * self.half_window + 1, lengths)
        w = int(wk.max())
        self._w = w
        self._wk = wk
        self._ar = np.arange(w)
        self._ar_f = self._ar.astype(float)
        self._ar_clip = np.minimum(self._ar[None, :], (wk - 1)[:, None])
        valid = self._ar[None, :] < wk[:, None]
        self._valid2 = np.concatenate([valid, valid]).astype(float)
        self._logmask = np.where(np.concatenate([valid, valid]), 0.0, -np.inf)
        self._back, self._fwd = transitions.weights()
        s = self._fwd.size - 1
        cols = np.arange(w + s + 1)[None, :] - 1
        wk2 = np.concatenate([wk, wk])
        self._beyond = (cols >= wk2[:, None]).astype(float)
        self._ext = np.zeros((2 * k, w + s + 1))
        self._last = np.concatenate([wk - 1, wk - 1])
        self._rows = np.arange(2 * k)
        self._max_lo = lengths - wk
        self._start_at_end = wk == lengths
        start_idx = (bank.starts[:, None] + self._ar_clip).ravel()
        self._start_means = np.ascontiguousarray(bank.means[start_idx])
        self._sqnorm = np.einsum("ij,ij->i", bank.means, bank.means)
        self._start_sq = self._sqnorm[start_idx]
        self._buf = np.empty((k * w, bank.dim))
        self._const = -bank.dim * math.log(self.sigma) - 0.5 * bank.dim * math.log(2.0 * math.pi)
        self.reset()

    def reset(self) -> None:
        """Forget the performance: every template waits at its first state (prior pi on state 1)."""
        k, w = self._k, self._w
        self.lo = np.zeros(k, dtype=np.intp)
        self.alpha = np.zeros((2 * k, w))
        self.alpha[:k, 0] = 1.0
        self.mean = np.zeros(k)
        self.var = np.zeros(k)
        self.entries = np.zeros(k, dtype=np.int64)
        self.steps = 0

    @property
    def log_constant(self) -> float:
        """The Gaussian's normalising term ``-d log sigma - d/2 log 2 pi`` included in every step."""
        return self._const

    def _emission(self, z: np.ndarray) -> np.ndarray:
        k, w = self._k, self._w
        idx = (self.bank.starts[:, None] + self.lo[:, None] + self._ar_clip).ravel()
        np.take(self.bank.means, idx, axis=0, out=self._buf)
        zz = float(z @ z)
        d2 = np.empty((2 * k, w))
        d2[:k] = (zz + self._sqnorm[idx] - 2.0 * (self._buf @ z)).reshape(k, w)
        d2[k:] = (zz + self._start_sq - 2.0 * (self._start_means @ z)).reshape(k, w)
        np.maximum(d2, 0.0, out=d2)
        d2 *= -0.5 / (self.sigma * self.sigma)
        d2 += self._logmask
        return d2

    def _predict(self) -> np.ndarray:
        k, w = self._k, self._w
        alpha, ext = self.alpha, self._ext
        ext.fill(0.0)
        if self._back > 0:
            ext[:, 0:w] += self._back * alpha
        for o, wo in enumerate(self._fwd):
            if wo > 0:
                ext[:, 1 + o:1 + o + w] += wo * alpha
        at_start = np.concatenate([self.lo == 0, np.ones(k, dtype=bool)])
        ext[:, 1] += ext[:, 0] * at_start
        at_end = np.concatenate([self.lo == self._max_lo, self._start_at_end])
        tail = np.einsum("ij,ij->i", ext, self._beyond)
        pred = ext[:, 1:w + 1] * self._valid2
        pred[self._rows, self._last] += tail * at_end
        return pred

    def step(self, z: np.ndarray) -> np.ndarray:
        """Advance every template by one standardised sample z (d,); returns the step's
        log-likelihood per template (K,). Updates ``mean`` (progress in states), ``var``
        (states squared), ``lo`` (window start) and ``entries`` (re-entries so far)."""
        k = self._k
        logb = self._emission(z)
        if self.steps == 0:
            pred = self.alpha.copy()
        else:
            pred = self._predict()
            total = pred[:k].sum(axis=1) + pred[k:].sum(axis=1)
            pred /= np.concatenate([total, total])[:, None]
            eps = self.transitions.restart
            if eps > 0:
                pred *= 1.0 - eps
                active = self.lo > 0
                pred[np.where(active, k + np.arange(k), np.arange(k)), 0] += eps
            if self.floor > 0:
                pred[:k] += self.floor * self._valid2[:k]
        lp = np.log(np.maximum(pred, _TINY))
        lp += logb
        lp3 = lp.reshape(2, k, self._w)
        m = lp3.max(axis=(0, 2))
        e = np.exp(lp3 - m[None, :, None])
        s = e.sum(axis=(0, 2))
        loglik = m + np.log(s) + self._const
        e /= s[None, :, None]
        self.alpha = e.reshape(2 * k, self._w)
        self.steps += 1
        self._settle()
        return loglik

    def _settle(self) -> None:
        k, alpha = self._k, self.alpha
        main, start = alpha[:k], alpha[k:]
        mass_main = main.sum(axis=1)
        switched = (start.sum(axis=1) > mass_main) & (self.lo > 0)
        if switched.any():
            main[switched] = start[switched]
            start[switched] = 0.0
            self.lo[switched] = 0
            self.entries[switched] += 1
            mass_main = main.sum(axis=1)
        mass_main = np.maximum(mass_main, _TINY)
        mu = (main @ self._ar_f) / mass_main
        self.var = np.maximum((main @ (self._ar_f ** 2)) / mass_main - mu ** 2, 0.0)
        self.mean = self.lo + mu
        new_lo = np.clip(np.rint(self.mean).astype(np.intp) - self.half_window, 0, self._max_lo)
        shift = new_lo - self.lo
        if shift.any():
            src = self._ar[None, :] + shift[:, None]
            ok = (src >= 0) & (src < self._w)
            moved = np.take_along_axis(main, np.clip(src, 0, self._w - 1), axis=1)
            main[:] = np.where(ok, moved, 0.0)
            self.lo = new_lo
        at_start = self.lo == 0
        if at_start.any() and start[at_start].any():
            main[at_start] += start[at_start]
            start[at_start] = 0.0

    @property
    def progress(self) -> np.ndarray:
        """Progress per template, 0 at its first state and 1 at its last (K,)."""
        return self.mean / (self.bank.lengths - 1)

    @property
    def progress_variance(self) -> np.ndarray:
        """Variance of the progress per template, in progress units squared (K,)."""
        return self.var / (self.bank.lengths - 1) ** 2


def forward_reference(states: np.ndarray, observations: np.ndarray, sigma: float,
                      half_window: int, transitions: Transitions) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Equations 2-7 written out for one template over a whole sequence, plainly (for checking).

    ``states`` (N, d) and ``observations`` (T, d) standardised. Returns per step the mean state,
    its variance (states squared) and the log-likelihood. No restart and no floor.
    """
    n = states.shape[0]
    w = min(2 * half_window + 1, n)
    back, fwd = transitions.weights()
    d = states.shape[1]
    const = -d * math.log(sigma) - 0.5 * d * math.log(2.0 * math.pi)
    alpha = np.zeros(n)
    lo = 0
    means, variances, logliks = [], [], []
    for t, o in enumerate(observations):
        logb = -0.5 * np.sum((states - o) ** 2, axis=1) / sigma ** 2
        window = np.zeros(n, dtype=bool)
        window[lo:lo + w] = True
        if t == 0:
            pred = np.zeros(n)
            pred[0] = 1.0
        else:
            alpha = np.where(window, alpha, 0.0)
            pred = np.zeros(n)
            for i in range(n):
                if back > 0:
                    pred[max(i - 1, 0)] += back * alpha[i]
                for off, wo in enumerate(fwd):
                    pred[min(i + off, n - 1)] += wo * alpha[i]
        pred = np.where(window, pred, 0.0)
        pred /= pred.sum()
        with np.errstate(divide="ignore"):
            lp = np.log(pred) + logb
        m = lp[window].max()
        a = np.where(window, np.exp(lp - m), 0.0)
        s = a.sum()
        logliks.append(m + math.log(s) + const)
        alpha = a / s
        idx = np.arange(n)
        mu = float(idx @ alpha)
        means.append(mu)
        variances.append(float(((idx - mu) ** 2) @ alpha))
        lo = int(np.clip(int(np.rint(mu)) - half_window, 0, n - w))
    return np.array(means), np.array(variances), np.array(logliks)
