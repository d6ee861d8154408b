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

Layout (for speed; :func:`forward_reference` is the same algorithm written plainly, one template
at a time): every template's window is a column of one ``(window, templates)`` array, so a step
is a few array operations over all templates of all followers at once, with no loop over
templates: emissions as squared distances from the window's prescaled states (kept gathered,
re-gathered only for the columns whose window moved), transitions as one banded matrix product,
per-template sums, minima and moments along the window axis. Where a main window lies on the
first states (``lo == 0``, most templates, waiting for their action) its first-states window
holds only this step's restart mass, so that window is not computed: its mass (restart x the
first state's emission) decides re-entry and is added to the main window's first state. Only
the first-states window's floor of 1e-100 per state is left out there, below 1e-90 of the main
window's own floor. With ``floor`` 0 (log domain) every first-states window is computed.
Measured on DESIGN's case (8 performers x 100 templates, one group, interleaved with the
previous layout of one row per window and both windows of every template computed): the step
takes 1.7 ms instead of 2.8 (median; p99 2.7 instead of 4.3), with the same outputs (1e-13).
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
    recover after the input left the template. ``step(z)`` takes one standardised sample (d,)
    or one per template (K, d). ``alpha`` (2K, w): rows ``0..K-1`` the main windows, rows
    ``K..2K-1`` the windows on the first states that catch a new performance.
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
        ar = np.arange(w)
        self._ar = ar[:, None]
        self._ar_k = ar[:, None] * k
        self._moments = np.stack([np.ones(w), ar, ar * ar]).astype(float)      # (3, w)
        self._max_lo = lengths - wk
        self._inv_span = 1.0 / (lengths - 1)
        self._cols = np.arange(k)
        valid = ar[:, None] < wk[None, :]                                       # (w, K)
        self._valid = valid.astype(float) if np.any(wk < w) else None
        back, fwd = transitions.weights()
        self._back = back
        # transitions inside a window as a banded matrix (targets x sources)
        trans = np.zeros((w, w))
        for o, wo in [(-1, back)] + list(enumerate(fwd)):
            i = np.arange(max(0, -o), min(w, w - o))
            trans[i + o, i] += wo
        self._trans = trans
        # mass moving past a template's last state folds onto it: from its window's row j,
        # every offset o >= max(1, wk - j), so rows wk-1, wk-2, ... weigh sum(fwd[i:])
        self._tail_rows = np.array([np.maximum(wk - i, 0) for i in range(1, len(fwd))],
                                   dtype=np.intp).reshape(-1, k)
        self._tail_w = np.array([np.where(wk - i >= 0, fwd[i:].sum(), 0.0) for i in range(1, len(fwd))],
                                dtype=float).reshape(-1, k)
        self._start_tail = wk == lengths   # a first-states window that reaches the last state
        # floor: keeps every main-window state reachable (and the normaliser >= floor, so the
        # clamp below never decides anything). With floor 0 the windows hold exact zeros and the
        # step is computed in the log domain exactly as the plain equations.
        # The floor is shared by the window's states (floor / states each), so the probability
        # that can jump anywhere in the window each step is ``floor`` whatever the window's
        # width: ``window`` sets reach only. Before, each state got the whole floor, and a still
        # puck was valid 47% of the time with window 40 (0% with 15).
        self._floor_main = (np.where(valid, self.floor / wk, 0.0) if self._valid is not None
                            else self.floor / wk)      # (w, K), or per column (K,) broadcast
        self._floor_start = np.where(valid, _START_FLOOR if self.floor > 0 else 0.0, 0.0).ravel()
        # log b = -|m - z|^2 / (2 sigma^2) + const: states and samples prescaled by 1 / (sigma
        # sqrt 2); a window's states past its template's end are infinitely far
        self._prescale = 1.0 / (self.sigma * math.sqrt(2.0))
        self._means_t = np.ascontiguousarray((bank.means * self._prescale).T)  # (d, states)
        self._ar_clip = np.minimum(ar[:, None], (wk - 1)[None, :])             # (w, K)
        self._mask_inf = np.where(valid, 0.0, np.inf).ravel()
        first = (bank.starts[None, :] + self._ar_clip).ravel()
        self._start_means = self._means_t[:, first]                            # (d, w K)
        self._start_means[0] += self._mask_inf
        self._mb = np.empty((bank.dim, w * k))    # the main windows' states, gathered
        self._mb_views = [m.reshape(w, k) for m in self._mb]
        self._lb = np.empty((w, k))               # scratch
        self._tmp = np.empty((w, k))
        self._q = np.empty((w, k))
        # dims: features really used per template (a group pads its inputs with zeros to one width)
        d = np.full(k, float(bank.dim)) if dims is None else np.asarray(dims, dtype=float)
        self._const = -d * math.log(self.sigma) - 0.5 * d * math.log(2.0 * math.pi)
        self.reset()

    def reset(self) -> None:
        """Forget the performance: every template waits at its first state (prior pi on state 1)."""
        k, w = self._k, self._w
        self.lo = np.zeros(k, dtype=np.intp)
        self._a = np.zeros((w, k))
        self._a[0] = 1.0
        self._b = np.zeros((w, k))
        self._s = np.ones(k)
        self.mean = np.zeros(k)
        self._mom = np.zeros((3, k))
        self._mom[0] = 1.0
        self.entries = np.zeros(k, dtype=np.int64)
        self.steps = 0
        self._fresh = np.zeros(k, dtype=bool)   # not stepped since reset_templates(fresh=True)
        self._n_fresh = 0
        self._gather(self._cols)

    def reset_templates(self, templates: np.ndarray, fresh: bool = False) -> None:
        """Forget the performance of some templates (indices): they wait at their first state,
        as after :meth:`reset`, while the others go on. ``fresh``: their next step is a first
        step too (no transitions, no restart), as after :meth:`reset`."""
        t = np.asarray(templates, dtype=np.intp)
        if t.size == 0:
            return
        if fresh and self.steps:
            self._fresh[t] = True
            self._n_fresh = int(np.count_nonzero(self._fresh))
        self._a[:, t] = 0.0
        self._a[0, t] = 1.0
        self._b[:, t] = 0.0
        self._s[t] = 1.0
        self.lo[t] = 0
        self.mean[t] = 0.0
        self._mom[:, t] = np.array([[1.0], [0.0], [0.0]])
        self._gather(t)

    @property
    def log_constant(self) -> np.ndarray:
        """Per template, the Gaussian's normalising term ``-d log sigma - d/2 log 2 pi`` (K,)."""
        return self._const

    @property
    def alpha(self) -> np.ndarray:
        """The windowed distributions (2K, w), normalised as the last step left them: main
        windows then first-states windows, each row over its window's states."""
        s = np.concatenate([self._s, self._s])
        return np.concatenate([self._a, self._b], axis=1).T / s[:, None]

    def _flat(self, cols: np.ndarray) -> np.ndarray:
        """Flat indices (w, n) into a (w, K) array of the columns ``cols``."""
        return self._ar_k + cols

    def _gather(self, cols: np.ndarray) -> None:
        """Gather the prescaled states of the main windows of ``cols`` (their ``lo`` changed)."""
        flat = self._flat(cols)
        idx = self._ar_clip.ravel()[flat] + (self.bank.starts[cols] + self.lo[cols])
        for mb, means in zip(self._mb, self._means_t):
            mb[flat] = means[idx]
        if self._valid is not None:
            self._mb[0][flat] += self._mask_inf[flat]

    def _transit(self, a: np.ndarray, out: np.ndarray, at_start: np.ndarray | float,
                 at_end: np.ndarray | None, cols: np.ndarray | None) -> np.ndarray:
        """The transitions applied inside windows ``a`` (w, n): sources and targets in the
        window, with folds at the template's first state (``at_start``) and last (``at_end``,
        None: nowhere); ``cols``: the templates of the columns (None: all)."""
        np.matmul(self._trans, a, out=out)
        if self._back > 0:
            out[0] += a[0] * (at_start * self._back)
        if at_end is not None and self._tail_rows.size:
            nf = self._tail_rows.shape[0]
            if self._valid is None and nf <= a.shape[0]:   # every window ends on its last row
                out[-1] += (self._tail_w[::-1, 0] @ a[a.shape[0] - nf:]) * at_end
            else:
                n = np.arange(a.shape[1])
                rows = self._tail_rows if cols is None else self._tail_rows[:, cols]
                w = self._tail_w if cols is None else self._tail_w[:, cols]
                tail = np.einsum("ij,ij->j", a.reshape(-1)[rows * n.size + n], w)
                out.reshape(-1)[(rows[0] * n.size + n)] += tail * at_end
        if self._valid is not None:
            out *= self._valid if cols is None else self._valid[:, cols]
        return out

    @staticmethod
    def _emission(mb: list, z: np.ndarray, out: np.ndarray, tmp: np.ndarray) -> np.ndarray:
        """-log b (equation 1) up to its constant: the squared distances of windows' states
        ``mb`` (d arrays (w, n)) from ``z`` (d, n or 1), both prescaled."""
        np.subtract(mb[0], z[0], out=out)
        np.square(out, out=out)
        for i in range(1, len(mb)):
            np.subtract(mb[i], z[i], out=tmp)
            np.square(tmp, out=tmp)
            out += tmp
        return out

    def step(self, z: np.ndarray) -> np.ndarray:
        """Advance every template by one standardised sample z (d,), or by one sample per
        template (K, d); returns the step's log-likelihood per template (K,). Updates ``mean``
        (progress in states), ``var`` (states squared), ``lo`` (window start) and ``entries``
        (re-entries so far)."""
        k, w = self._k, self._w
        zt = z[:, None] if z.ndim == 1 else np.ascontiguousarray(z.T)
        first = self.steps == 0
        eps = 0.0 if first else self.transitions.restart
        fresh = np.flatnonzero(self._fresh) if self._n_fresh and not first else None
        if fresh is not None:   # templates reset afresh take a first step: no restart mass
            eps = np.where(self._fresh, 0.0, eps)
        logs = self.floor <= 0
        at_start = self.lo == 0
        zt = zt * self._prescale
        lb = self._emission(self._mb_views, zt, self._lb, self._tmp)    # -log b, see below
        # the first-states windows computed in full: where the main window is elsewhere (with
        # floor 0, everywhere: no floor-sized terms are dropped then)
        sc = self._cols if logs else np.flatnonzero(self.lo)
        ns = sc.size
        if ns:
            fs = self._flat(sc)
            lbs = self._emission([m[fs] for m in self._start_means],
                                 zt if zt.shape[1] == 1 else zt[:, sc], np.empty((w, ns)),
                                 np.empty((w, ns)))
            bs = self._b.reshape(-1)[fs]
        if first:
            q = np.add(self._a, self._floor_main, out=self._q)
            if ns:
                qs = bs + self._floor_start[fs]
        else:
            q = self._transit(self._a, self._q, at_start, (self.lo == self._max_lo), None)
            tot = q.sum(axis=0)
            if ns:
                ends = self._start_tail[sc]
                qs = self._transit(bs, np.empty_like(bs), 1.0, ends if ends.any() else None, sc)
                tot[sc] += qs.sum(axis=0)
            c = (1.0 - eps) / tot
            q *= c
            q += self._floor_main
            if ns:
                qs *= c[sc]
                qs += self._floor_start[fs]
                qs[0] += eps if fresh is None else eps[sc]
            if fresh is not None:
                floor = self._floor_main if np.ndim(self._floor_main) == 1 else self._floor_main[:, fresh]
                q[:, fresh] = self._a[:, fresh] + (floor[fresh] if np.ndim(floor) == 1 else floor)
                if ns:
                    at = np.flatnonzero(self._fresh[sc])
                    if at.size:
                        qs[:, at] = bs[:, at] + self._floor_start[fs[:, at]]
        # m: per template, the smallest distance (the largest log b) of its windows
        if not logs:
            m = lb.min(axis=0)
            if ns:
                ms = np.minimum(m[sc], lbs.min(axis=0))
                m[sc] = ms
                np.subtract(ms, lbs, out=lbs)
                np.maximum(lbs, _CLAMP, out=lbs)
                qs *= np.exp(lbs, out=lbs)
            np.subtract(m, lb, out=lb)
            np.maximum(lb, _CLAMP, out=lb)
            e = np.exp(lb, out=lb)
            q *= e
        else:
            with np.errstate(divide="ignore"):
                lq, lqs = np.log(q), np.log(qs)
            lq -= lb
            lqs -= lbs
            m = -np.maximum(lq.max(axis=0), lqs.max(axis=0))
            for a in (lq, lqs):
                a += m
                np.maximum(a, -600.0, out=a)  # no subnormal numbers: far slower to compute with
            q, qs = np.exp(lq, out=q), np.exp(lqs, out=lqs)
            e = None
        mom = self._moments @ q
        s = mom[0].copy()
        # where the main window is on the first states, the first-states window holds the
        # restart mass at the first state only (plus its 1e-100 floor, left out)
        restart = e[0] * eps * at_start if not logs else None
        if restart is not None:
            s += restart
        if ns:
            s[sc] += qs.sum(axis=0)
        self._a, self._q = q, self._a
        self._s = s
        self.steps += 1
        if fresh is not None:
            self._fresh[fresh] = False
            self._n_fresh = 0
        self._settle(mom, (qs, fs) if ns else None, sc, restart, e, eps)
        return np.log(s) - m + self._const

    def _start_row(self, cols: np.ndarray, e: np.ndarray, eps: float | np.ndarray) -> np.ndarray:
        """The first-states windows of ``cols`` where they were not computed: this step's
        restart mass ``eps`` and floor times the emissions ``e`` (their main windows' own)."""
        b = e[:, cols] * _START_FLOOR
        b[0] += e[0, cols] * (eps if np.ndim(eps) == 0 else eps[cols])
        return b if self._valid is None else b * self._valid[:, cols]

    def _settle(self, mom: np.ndarray, start: tuple | None, sc: np.ndarray,
                restart: np.ndarray | None, e: np.ndarray | None, eps: float | np.ndarray) -> None:
        """Re-entry, progress mean and variance (equations 3-4), and the window for the next step."""
        a, b, w, k = self._a, self._b, self._w, self._k
        af, bf = a.reshape(-1), b.reshape(-1)
        lo_before = lo0 = self.lo
        # a new performance holds more probability than the one followed so far: re-entry
        start_mass = np.zeros(k) if restart is None else restart.copy()
        if start is not None:
            bs, fs = start
            start_mass[sc] = bs.sum(axis=0)
            bf[fs] = bs
        switched = start_mass > mom[0]
        if np.count_nonzero(switched):
            sw = np.flatnonzero(switched)
            computed = lo0[sw] > 0 if restart is not None else np.ones(sw.size, dtype=bool)
            a[:, sw[computed]] = b[:, sw[computed]]
            if not computed.all():
                a[:, sw[~computed]] = self._start_row(sw[~computed], e, eps)
            b[:, sw] = 0.0
            self.entries[sw] += 1
            lo0 = lo0.copy()
            lo0[sw] = 0
            mom[:, sw] = self._moments @ a[:, sw]
            if restart is not None:
                restart[sw] = 0.0       # its window is now the main one: nothing more to merge
        self._mom = mom
        self.mean = lo0 + mom[1] / mom[0]
        new_lo = np.minimum(np.maximum((self.mean + 0.5).astype(np.intp) - self.half_window, 0),
                            self._max_lo)
        shift = new_lo - lo0
        moved = np.flatnonzero(shift)
        if moved.size:
            src = self._ar + shift[moved]             # (w, n) rows the window's rows come from
            inside = (src >= 0) & (src < w)
            dst = self._flat(moved)
            af[dst] = af[np.clip(src, 0, w - 1) * k + moved] * inside
            if restart is not None:
                # a main window leaving the first states: its first-states window is this step's
                left = moved[(lo_before[moved] == 0) & ~switched[moved]]
                if left.size:
                    b[:, left] = self._start_row(left, e, eps)
                    restart[left] = 0.0
        self.lo = new_lo
        # where the two windows coincide they are one
        if restart is not None:
            a[0] += restart * (new_lo == 0)
        if start is not None:
            back = sc[new_lo[sc] == 0]
            if back.size:
                fb = self._flat(back)
                af[fb] += bf[fb]
                bf[fb] = 0.0
        regather = np.flatnonzero(new_lo != lo_before)
        if regather.size:
            self._gather(regather)

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
        return (t, self._a[:, t].copy(), self._b[:, t].copy(), self._s[t].copy(), self.lo[t].copy(),
                self.mean[t].copy(), self._mom[:, t].copy(), self.entries[t].copy(),
                self._fresh[t].copy() if self.steps else np.ones(len(t), dtype=bool))

    def restore(self, saved: tuple) -> None:
        """Put back what :meth:`snapshot` saved (those templates skip the step in between)."""
        t, a, b, s, lo, mean, mom, entries, fresh = saved
        self._a[:, t], self._b[:, t], self._s[t] = a, b, s
        self.lo[t], self.mean[t], self._mom[:, t], self.entries[t] = lo, mean, mom, entries
        self._fresh[t] = fresh
        self._n_fresh = int(np.count_nonzero(self._fresh))
        self._gather(t)

    @property
    def progress(self) -> np.ndarray:
        """Progress per template, 0 at its first state and 1 at its last (K,)."""
        return self.mean * self._inv_span


def forward_reference(states: np.ndarray, observations: np.ndarray, sigma: float, half_window: int,
                      transitions: Transitions, floor: float = 0.0
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:class:`WindowedForward` written out plainly for one template over a whole sequence, state
    by state (equations 2-7, the floor, the first-states window and re-entry), for checking.

    ``states`` (N, d) and ``observations`` (T, d) standardised. Returns per step the mean state,
    its variance (states squared), the log-likelihood and the re-entries so far.
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

    def move(a: np.ndarray, window: np.ndarray) -> np.ndarray:
        """Every state's probability moved by the transitions; what leaves the window is lost,
        what would go before the first state or past the last stays there."""
        pred = np.zeros(n)
        for i in np.flatnonzero(window):
            for j, wo in [(max(i - 1, 0), back)] + [(min(i + o, n - 1), f) for o, f in enumerate(fwd)]:
                if window[j]:
                    pred[j] += wo * a[i]
        return pred

    for t, o in enumerate(observations):
        logb = -0.5 * np.sum((states - o) ** 2, axis=1) / sigma ** 2
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
