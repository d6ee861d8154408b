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

_START_FLOOR = 1e-100  # keeps the first-states windows' products far from subnormal numbers
_CLAMP = -200.0  # log-weights below the window's best by more than this count as e^-200


class WindowedForward:
    """Windowed forward algorithm over every template of a bank at once (stateful).

    ``sigma``: observation standard deviation in standardised feature units; ``half_window``: p,
    in states; ``floor``: probability added to each main-window state per step so a follower can
    recover after the input left the template. ``step(z)`` takes one standardised sample (d,).
    Rows ``0..K-1`` of ``alpha`` are the main windows, rows ``K..2K-1`` the windows on the first
    states that catch a new performance.
    """

    def __init__(self, bank: TemplateBank, sigma: float = 0.2, half_window: int = 15,
                 transitions: Transitions = Transitions(), floor: float = 1e-8,
                 dims: np.ndarray | None = None) -> None:
        if not (sigma > 0 and math.isfinite(sigma)):
            raise ValueError(f"sigma must be a positive number, got {sigma}")
        if int(half_window) < 1:
            raise ValueError(f"half_window must be at least 1 state, got {half_window}")
        self.bank = bank
        self.sigma = float(sigma)
        self.half_window = int(half_window)
        self.transitions = transitions
        self.floor = float(floor)
        k, lengths = len(bank.names), bank.lengths
        wk = np.minimum(2 * self.half_window + 1, lengths)
        w = int(wk.max())
        self._k, self._w, self._wk = k, w, wk
        self._ar = np.arange(w)
        self._ar_f = self._ar.astype(float)
        self._moments = np.stack([np.ones(w), self._ar_f, self._ar_f ** 2], axis=1)
        self._max_lo = lengths - wk
        self._inv_span = 1.0 / (lengths - 1)
        self._has_short = bool(np.any(wk < w))
        valid = self._ar[None, :] < wk[:, None]
        self._valid2 = np.concatenate([valid, valid]).astype(float)
        # transitions as a banded matrix (sources x targets) plus folds at the template ends
        back, fwd = transitions.weights()
        self._back = back
        trans = np.zeros((w, w))
        for o, wo in [(-1, back)] + list(enumerate(fwd)):
            if wo > 0:
                i = np.arange(max(0, -o), min(w, w - o))
                trans[i, i + o] += wo
        self._trans = trans
        tail = np.zeros((2 * k, w))
        for r, n_w in enumerate(np.concatenate([wk, wk])):
            for o, wo in enumerate(fwd):
                if o > 0 and wo > 0:
                    tail[r, max(0, n_w - o):n_w] += wo
        self._tail = tail
        self._last_flat = np.concatenate([wk - 1, wk - 1]) + np.arange(2 * k) * w
        self._at_end = np.concatenate([np.zeros(k), (wk == lengths).astype(float)])
        self._fold = np.full(2 * k, back)
        # floor: keeps every main-window state reachable (and the normaliser >= floor, so the
        # clamp below never decides anything). With floor 0 the windows hold exact zeros and the
        # step is computed in the log domain exactly as the plain equations.
        # The floor is shared by the window's states (floor / states each), so the probability
        # that can jump anywhere in the window each step is ``floor`` whatever the window's
        # width: ``window`` sets reach only. Before, each state got the whole floor, and a still
        # puck was valid 47% of the time with window 40 (0% with 15).
        self._floor = np.full((2 * k, w), _START_FLOOR if self.floor > 0 else 0.0)
        self._floor[:k] = np.where(valid, self.floor / wk[:, None], self._floor[:k])
        # the gathered states: main windows move, the first-states windows are fixed
        ar_clip = np.minimum(self._ar[None, :], (wk - 1)[:, None])
        self._gather_base = (bank.starts[:, None] + ar_clip).ravel()
        # log b = (m.z - |m|^2 / 2) / sigma^2 - |z|^2 / (2 sigma^2) + const: states prescaled
        self._inv_var = 1.0 / (self.sigma * self.sigma)
        self._means_s = np.ascontiguousarray(bank.means * self._inv_var)
        sqnorm = np.einsum("ij,ij->i", bank.means, bank.means)
        self._half_sq_states = 0.5 * sqnorm * self._inv_var
        self._buf = np.empty((2 * k * w, bank.dim))
        self._buf[k * w:] = self._means_s[self._gather_base]
        self._half_sq = np.empty(2 * k * w)
        self._half_sq[k * w:] = self._half_sq_states[self._gather_base]
        masked = ~np.concatenate([valid, valid]).ravel()
        self._half_sq[k * w:][masked[k * w:]] = np.inf
        self._mask_main = np.where(masked[:k * w], np.inf, 0.0) if self._has_short else None
        # dims: features really used per template (a group pads its inputs with zeros to one width)
        d = np.full(k, float(bank.dim)) if dims is None else np.asarray(dims, dtype=float)
        self._const = -d * math.log(self.sigma) - 0.5 * d * math.log(2.0 * math.pi)
        self._pad = np.zeros((k, 3 * w))
        self._pad_base = (np.arange(k) * 3 * w + w)[:, None] + self._ar[None, :]
        self.reset()

    def reset(self) -> None:
        """Forget the performance: every template waits at its first state (prior pi on state 1)."""
        k, w = self._k, self._w
        self.lo = np.zeros(k, dtype=np.intp)
        self.alpha = np.zeros((2 * k, w))
        self.alpha[:k, 0] = 1.0
        self.mean = np.zeros(k)
        self._mom = np.tile([1.0, 0.0, 0.0], (k, 1))
        self.entries = np.zeros(k, dtype=np.int64)
        self.steps = 0
        self._window_moved()

    def reset_templates(self, templates: np.ndarray) -> None:
        """Forget the performance of some templates (indices): they wait at their first state,
        as after :meth:`reset`, while the others go on."""
        templates = np.asarray(templates, dtype=np.intp)
        if templates.size == 0:
            return
        k = self._k
        self.alpha[templates] = 0.0
        self.alpha[templates, 0] = 1.0
        self.alpha[templates + k] = 0.0
        self.lo[templates] = 0
        self.mean[templates] = 0.0
        self._mom[templates] = (1.0, 0.0, 0.0)
        self._window_moved()

    @property
    def log_constant(self) -> np.ndarray:
        """Per template, the Gaussian's normalising term ``-d log sigma - d/2 log 2 pi`` (K,)."""
        return self._const

    def _emission(self, z: np.ndarray) -> np.ndarray:
        """log b (equation 1) for every window state, up to the constant -|z|^2 / (2 sigma^2)."""
        kw = self._k * self._w
        idx = self._idx
        np.take(self._means_s, idx, axis=0, out=self._buf[:kw])
        np.take(self._half_sq_states, idx, out=self._half_sq[:kw])
        if self._mask_main is not None:
            self._half_sq[:kw] += self._mask_main
        if z.ndim == 1:
            lb = self._buf @ z
        else:
            k, w = self._k, self._w
            lb = np.matmul(self._buf.reshape(2 * k, w, -1), np.concatenate([z, z])[:, :, None]).reshape(-1)
        lb -= self._half_sq
        return lb.reshape(2 * self._k, self._w)

    def _predict(self) -> np.ndarray:
        """The transitions applied inside each window (sources and targets in the window)."""
        k = self._k
        alpha = self.alpha
        pred = alpha @ self._trans
        pred[:, 0] += alpha[:, 0] * self._fold
        if self._has_short:
            pred.reshape(-1)[self._last_flat] += np.einsum("ij,ij->i", alpha, self._tail) * self._at_end
            pred *= self._valid2
        else:
            pred[:k, -1] += (alpha[:k] @ self._tail[0]) * self._at_end[:k]
        return pred

    def _window_moved(self) -> None:
        """Refresh what depends on the window starts ``lo``: gather indices and end folds."""
        k = self._k
        self._idx = self._gather_base + np.repeat(self.lo, self._w)
        at_start = self.lo == 0
        self._fold[:k] = at_start * self._back
        self._at_start = at_start[:, None]
        self._at_end[:k] = self.lo == self._max_lo

    def step(self, z: np.ndarray) -> np.ndarray:
        """Advance every template by one standardised sample z (d,), or by one sample per
        template (K, d); returns the step's log-likelihood per template (K,). Updates ``mean``
        (progress in states), ``var`` (states squared), ``lo`` (window start) and ``entries``
        (re-entries so far)."""
        k, w = self._k, self._w
        lb = self._emission(z)
        if self.steps == 0:
            pred = self.alpha + self._floor
        else:
            pred = self._predict()
            p3 = pred.reshape(2, k, w)
            eps = self.transitions.restart
            p3 *= (1.0 - eps) / p3.sum(axis=(0, 2))[:, None]
            pred += self._floor
            # a new performance starts at the first state; where the main window is on the first
            # states the two windows coincide and are merged in _settle
            pred[k:, 0] += eps
        lb3 = lb.reshape(2, k, w)
        if self.floor > 0:
            m = lb3.max(axis=(0, 2))
            lb3 -= m[:, None]
            np.maximum(lb, _CLAMP, out=lb)
            np.exp(lb, out=lb)
            pred *= lb
        else:
            with np.errstate(divide="ignore"):
                lp = np.log(pred)
            lp += lb
            lp3 = lp.reshape(2, k, w)
            m = lp3.max(axis=(0, 2))
            lp3 -= m[:, None]
            np.maximum(lp, -600.0, out=lp)  # no subnormal numbers: far slower to compute with
            pred = np.exp(lp, out=lp)
        if self._has_short:
            pred *= self._valid2
        p3 = pred.reshape(2, k, w)
        s = p3.sum(axis=(0, 2))
        p3 /= s[:, None]
        self.alpha = pred
        self.steps += 1
        self._settle()
        zz = float(z @ z) if z.ndim == 1 else np.einsum("kd,kd->k", z, z)
        return m + np.log(s) + (self._const - 0.5 * self._inv_var * zz)

    def _settle(self) -> None:
        """Re-entry, progress mean and variance (equations 3-4), and the window for the next step."""
        k, w, alpha = self._k, self._w, self.alpha
        main, start = alpha[:k], alpha[k:]
        mom = alpha @ self._moments
        # a new performance holds more probability than the one followed so far: re-entry
        switched = mom[k:, 0] > mom[:k, 0]
        moved = False
        if np.count_nonzero(switched):
            main[switched] = start[switched]
            start[switched] = 0.0
            self.lo[switched] = 0
            self.entries[switched] += 1
            mom = alpha @ self._moments
            moved = True
        self._mom = mom = mom[:k]
        self.mean = self.lo + mom[:, 1] / mom[:, 0]
        new_lo = np.minimum(np.maximum((self.mean + 0.5).astype(np.intp) - self.half_window, 0),
                            self._max_lo)
        shift = new_lo - self.lo
        if np.count_nonzero(shift):
            self._pad[:, w:2 * w] = main
            main[:] = self._pad.reshape(-1)[self._pad_base + shift[:, None]]
            self.lo = new_lo
            moved = True
        if moved:
            self._window_moved()
        if np.count_nonzero(self.lo) < k:  # where the two windows coincide they are one
            np.add(main, start * self._at_start, out=main)
            np.multiply(start, ~self._at_start, out=start)

    @property
    def var(self) -> np.ndarray:
        """Variance of the main-window distribution per template, in states squared (K,)."""
        mom = self._mom
        mu = mom[:, 1] / mom[:, 0]
        return np.maximum(mom[:, 2] / mom[:, 0] - mu * mu, 0.0)

    def var_of(self, i: int) -> float:
        """:attr:`var` of template ``i`` alone (cheaper)."""
        m0, m1, m2 = self._mom[i].tolist()
        return max(m2 / m0 - (m1 / m0) ** 2, 0.0)

    def snapshot(self, templates: np.ndarray) -> tuple:
        """The state of some templates (indices), to :meth:`restore` after a step."""
        rows = np.concatenate([templates, templates + self._k])
        return (templates, self.alpha[rows].copy(), self.lo[templates].copy(),
                self.mean[templates].copy(), self._mom[templates].copy(), self.entries[templates].copy())

    def restore(self, saved: tuple) -> None:
        """Put back what :meth:`snapshot` saved (those templates skip the step in between)."""
        templates, alpha, lo, mean, mom, entries = saved
        self.alpha[np.concatenate([templates, templates + self._k])] = alpha
        self.lo[templates], self.mean[templates], self._mom[templates] = lo, mean, mom
        self.entries[templates] = entries
        self._window_moved()

    @property
    def progress(self) -> np.ndarray:
        """Progress per template, 0 at its first state and 1 at its last (K,)."""
        return self.mean * self._inv_span



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
        lo = int(np.clip(math.floor(mu + 0.5) - half_window, 0, n - w))
    return np.array(means), np.array(variances), np.array(logliks)
