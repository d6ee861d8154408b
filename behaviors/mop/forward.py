"""The forward algorithm on a sliding window (MOP section 3.2.2, equations 2-7), for many templates.

Every template keeps a window of ``2p + 1`` states around its progress mean (equation 7, with
``i_inf = N - 2p`` near the end; a template shorter than the window is followed whole). Each step
the windowed distribution is moved by the transitions, renormalised (equation 6's ``k``),
multiplied by the Gaussian observation probabilities and renormalised again; the logarithm of
that normaliser is the step's log-likelihood (equation 2 kept as a running sum of logs, so runs
of any length stay finite). Progress is the mean state (equation 3), its spread the variance
(equation 4).

Besides the main window, each template keeps a second window on its first states fed by the
restart probability: when that window holds more probability than the main one, a new
performance has begun and it becomes the main window (re-entry).

The step itself is compiled (:mod:`behaviors.mop.window_kernel`), one short fused loop per
template over its window; :func:`forward_reference` is the same algorithm written plainly, one
template at a time, for checking.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.mop.hmm import TemplateBank, Transitions, dwell_states
from behaviors.mop.window_kernel import (CLAMP as _CLAMP, START_FLOOR as _START_FLOOR,
                                         seat_windows, step_windows)


class WindowedForward:
    """Windowed forward algorithm over every template of a bank at once (stateful).

    ``sigma``: observation standard deviation in standardised feature units; ``half_window``: p,
    in states; ``floor``: probability added to each main-window state per step so a follower can
    recover after the input left the template (shared by the window's states, so ``window`` sets
    reach only: with the whole floor on each state a still puck was valid 47% of the time with
    window 40, 0% with 15; with ``floor`` 0 the step runs in the log domain exactly as the plain
    equations). ``step(z)`` takes one standardised sample (d,) or one per template (K, d).
    ``alpha`` (2K, w): rows ``0..K-1`` the main windows, rows ``K..2K-1`` the windows on the
    first states that catch a new performance.
    """

    def __init__(self, bank: TemplateBank, sigma: float = 0.2, half_window: int = 15,
                 transitions: Transitions = Transitions(), floor: float = 1e-8,
                 dims: np.ndarray | None = None, stay: np.ndarray | None = None,
                 stretch: tuple[np.ndarray, np.ndarray] | None = None) -> None:
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
        self._k = k
        self._wk = np.minimum(2 * self.half_window + 1, lengths).astype(np.int64)
        self._w = int(self._wk.max())
        self._max_lo = (lengths - self._wk).astype(np.int64)
        self._starts = np.asarray(bank.starts, dtype=np.int64)
        self._start_tail = self._wk == lengths   # a first-states window that reaches the last state
        self._inv_span = 1.0 / (lengths - 1)
        self._back, self._fwd = transitions.weights()
        # log b = -|m - z|^2 / (2 sigma^2) + const: states and samples prescaled by
        # 1 / (sigma sqrt 2)
        self._prescale = 1.0 / (self.sigma * math.sqrt(2.0))
        self._means = np.ascontiguousarray(bank.means * self._prescale)
        self._z = np.empty((k, bank.dim))
        self._ll = np.empty(k)
        # dims: features really used per template (a group pads its inputs with zeros to one width)
        d = np.full(k, float(bank.dim)) if dims is None else np.asarray(dims, dtype=float)
        self._const = -d * math.log(self.sigma) - 0.5 * d * math.log(2.0 * math.pi)
        # holds inside a template: a share of each hold state's probability stays (hmm.dwell_states;
        # ``stay`` (states,) given: a group's, each member's own)
        self._stay = (dwell_states(bank, transitions.dwell) if stay is None
                      else np.ascontiguousarray(stay, dtype=float))
        # each state's stretch along its path (behaviors.mop.stretch; none given: points, as
        # the paper's states), the half-length prescaled as the states
        tangent, half = stretch if stretch is not None else (np.zeros_like(bank.means),
                                                              np.zeros(len(bank.means)))
        self._tangent = np.ascontiguousarray(tangent, dtype=float)
        self._half = np.ascontiguousarray(np.asarray(half, dtype=float) * self._prescale)
        # ... and its density spread over its length: minus log of its normaliser over a
        # point's, 1 + 2 half / (sqrt(2 pi) sigma), in the prescaled distances' nats
        self._lift = np.log1p(self._half * (2.0 / math.sqrt(math.pi)))
        self._stretched = (np.logical_or.reduceat(self._half > 0, self._starts) if k
                           else np.zeros(0, bool))
        # step_windows' scratch: seven windows rounded up to whole vectors of eight states
        self._scratch = np.empty((7, (self._w + 7) // 8 * 8))
        self._dwells = np.logical_or.reduceat(self._stay > 0, self._starts) \
            if k else np.zeros(0, bool)
        self.reset()

    def reset(self) -> None:
        """Forget the performance: every template waits at its first state (prior pi on state 1)."""
        k, w = self._k, self._w
        self.lo = np.zeros(k, dtype=np.int64)
        self._a = np.zeros((k, w))
        self._a[:, 0] = 1.0
        self._b = np.zeros((k, w))
        self._s = np.ones(k)
        self.mean = np.zeros(k)
        self._mom = np.zeros((3, k))
        self._mom[0] = 1.0
        self.entries = np.zeros(k, dtype=np.int64)
        self.steps = 0
        # the next step is a first one (no transitions, no restart)
        self._fresh = np.ones(k, dtype=bool)

    def reset_templates(self, templates: np.ndarray | slice, fresh: bool = False) -> None:
        """Forget the performance of some templates (indices or a slice): they wait at their
        first state, as after :meth:`reset`, while the others go on. ``fresh``: their next step
        is a first step too (no transitions, no restart), as after :meth:`reset`."""
        t = templates if isinstance(templates, slice) else np.asarray(templates, dtype=np.intp)
        if not isinstance(t, slice) and t.size == 0:
            return
        self._fresh[t] |= fresh
        self._a[t] = 0.0
        self._a[t, 0] = 1.0
        self._b[t] = 0.0
        self._s[t] = 1.0
        self.lo[t] = 0
        self.mean[t] = 0.0
        self._mom[:, t] = np.array([[1.0], [0.0], [0.0]])

    @property
    def log_constant(self) -> np.ndarray:
        """Per template, the Gaussian's normalising term ``-d log sigma - d/2 log 2 pi`` (K,)."""
        return self._const

    @property
    def alpha(self) -> np.ndarray:
        """The windowed distributions (2K, w), normalised as the last step left them: main
        windows then first-states windows, each row over its window's states."""
        s = np.concatenate([self._s, self._s])
        return np.concatenate([self._a, self._b]) / s[:, None]

    def step(self, z: np.ndarray) -> np.ndarray:
        """Advance every template by one standardised sample z (d,), or by one sample per
        template (K, d); returns the step's log-likelihood per template (K,). Updates ``mean``
        (progress in states), ``var`` (states squared), ``lo`` (window start) and ``entries``
        (re-entries so far)."""
        np.multiply(z, self._prescale, out=self._z)
        step_windows(self._means, self._starts, self._wk, self._max_lo, self._start_tail, self._z,
                     self._a, self._b, self._s, self.lo, self.mean, self._mom, self.entries,
                     self._fresh, self.half_window, self._back, self._fwd,
                     self.transitions.restart, self.floor, self._const, self._ll,
                     self._stay, self._dwells, self._scratch, self._tangent, self._half,
                     self._lift, self._stretched)
        self.steps += 1   # (``_fresh`` cleared by step_windows)
        return self._ll.copy()

    @property
    def var(self) -> np.ndarray:
        """Variance of the main-window distribution per template, in states squared (K,)."""
        m0, m1, m2 = self._mom
        mu = m1 / m0
        return np.maximum(m2 / m0 - mu * mu, 0.0)

    def var_of(self, i: int) -> float:
        """:attr:`var` of template ``i`` alone (cheaper)."""
        m0, m1, m2 = self._mom[:, i].tolist()
        return max(m2 / m0 - (m1 / m0) ** 2, 0.0)

    def snapshot(self, templates: np.ndarray) -> tuple:
        """The state of some templates (indices), to :meth:`restore` after a step."""
        t = templates
        return (t, self._a[t], self._b[t], self._s[t], self.lo[t], self.mean[t],
                self._mom[:, t], self.entries[t], self._fresh[t])

    def restore(self, saved: tuple) -> None:
        """Put back what :meth:`snapshot` saved (those templates skip the step in between)."""
        t, a, b, s, lo, mean, mom, entries, fresh = saved
        self._a[t], self._b[t], self._s[t], self._fresh[t] = a, b, s, fresh
        self.lo[t], self.mean[t], self._mom[:, t], self.entries[t] = lo, mean, mom, entries

    def seat(self, states: np.ndarray, seated: np.ndarray) -> None:
        """Each template whose ``states`` (K,: a state from its first, -1 none) lies ahead of its
        mean is followed from there: its main window's whole probability on that state
        (:func:`~behaviors.mop.holding.rested_sizes`), marked in ``seated`` (K,). ``states`` is
        cleared to -1 (compiled: :func:`~behaviors.mop.window_kernel.seat_windows`)."""
        seat_windows(states, seated, self.mean, self._a, self._s, self.lo, self._mom,
                     self._max_lo, self.half_window)

    @property
    def progress(self) -> np.ndarray:
        """Progress per template, 0 at its first state and 1 at its last (K,)."""
        return self.mean * self._inv_span


def forward_reference(states: np.ndarray, observations: np.ndarray, sigma: float, half_window: int,
                      transitions: Transitions, floor: float = 0.0, stay: np.ndarray | None = None,
                      stretch: tuple[np.ndarray, np.ndarray] | None = None
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:class:`WindowedForward` written out plainly for one template over a whole sequence, state
    by state (equations 2-7, the floor, the first-states window and re-entry), for checking.

    ``states`` (N, d) and ``observations`` (T, d) standardised; ``stay`` (N,): each state's
    share that stays before the transitions move the rest (none by default); ``stretch``:
    each state's unit direction (N, d) and half-length (N,) along its path
    (:mod:`behaviors.mop.stretch`; none by default: points). Returns per step the
    mean state, its variance (states squared), the log-likelihood and the re-entries so far.
    """
    n, d = states.shape
    w = min(2 * half_window + 1, n)
    back, fwd = transitions.weights()
    eps = transitions.restart
    const = -d * math.log(sigma) - 0.5 * d * math.log(2.0 * math.pi)
    main, start = np.zeros(n), np.zeros(n)
    main[0] = 1.0
    first = np.arange(n) < w
    lo, entries = 0, 0
    out = []
    held = np.zeros(n) if stay is None else np.asarray(stay, dtype=float)

    def move(a: np.ndarray, window: np.ndarray) -> np.ndarray:
        """Every state's probability moved by the transitions; what leaves the window is lost,
        what would go before the first state or past the last stays there."""
        pred = np.zeros(n)
        for i in np.flatnonzero(window):
            moving = a[i] * (1.0 - held[i])
            pred[i] += a[i] - moving
            for j, wo in [(max(i - 1, 0), back)] + [(min(i + o, n - 1), f)
                                                    for o, f in enumerate(fwd)]:
                if window[j]:
                    pred[j] += wo * moving
        return pred

    for t, o in enumerate(observations):
        gap = states - o
        d2 = np.sum(gap ** 2, axis=1)
        if stretch is not None:   # the part along a stretched state, up to its half-length
            along = np.abs(np.sum(gap * stretch[0], axis=1))
            c = np.minimum(stretch[1], along)
            d2 = d2 - c * (2.0 * along - c)
        logb = -0.5 * d2 / sigma ** 2
        if stretch is not None:   # spread over its length
            logb = logb - np.log1p(stretch[1] * (2.0 / (math.sqrt(2.0 * math.pi) * sigma)))
        window = (np.arange(n) >= lo) & (np.arange(n) < lo + w)
        if t == 0:
            pm, ps = main.copy(), start.copy()
        else:
            pm, ps = move(main, window), move(start, first)
            total = pm.sum() + ps.sum()
            pm, ps = pm * (1.0 - eps) / total, ps * (1.0 - eps) / total
        pm[window] += floor / w
        ps[first] += _START_FLOOR if floor > 0 else 0.0
        ps[0] += eps if t > 0 else 0.0
        both = window | first
        if floor > 0:
            m = logb[both].max()
            e = np.exp(np.maximum(np.where(both, logb - m, _CLAMP), _CLAMP))
            pm, ps = pm * e * window, ps * e * first
        else:
            with np.errstate(divide="ignore"):
                lm, ls = np.log(pm) + logb, np.log(ps) + logb
            m = max(lm[window].max(), ls[first].max())
            pm = np.exp(np.maximum(np.where(window, lm - m, -np.inf), -600.0)) * window
            ps = np.exp(np.maximum(np.where(first, ls - m, -np.inf), -600.0)) * first
        s = pm.sum() + ps.sum()
        main, start = pm / s, ps / s
        if start.sum() > main.sum():                  # a new performance began: re-entry
            main, start, lo, entries = start, np.zeros(n), 0, entries + 1
        idx = np.arange(n)
        mu = float(idx @ main) / main.sum()
        var = max(float((idx * idx) @ main) / main.sum() - mu * mu, 0.0)
        out.append((mu, var, m + math.log(s) + const, entries))
        lo = int(np.clip(math.floor(mu + 0.5) - half_window, 0, n - w))
        main = np.where((idx >= lo) & (idx < lo + w), main, 0.0)
        if lo == 0:                                   # the two windows coincide: they are one
            main, start = main + start, np.zeros(n)
    mean, variance, logliks, entered = (np.array(c) for c in zip(*out))
    return mean, variance, logliks, entered
