"""Follow, recognise and spot several actions at once (MOP section 3.2 with several templates).

:class:`ActionFollower` maps each live sample into every template's own units, advances the
windowed forward algorithm of every template by one sample (:mod:`behaviors.mop.forward`), and
reports for the most probable template its progress (0..1), variance and mean per-sample
log-likelihood, plus every template's probability and progress. Figures below come from
``bench/follow_quality.py`` (puck paths: six drawn gestures and fourteen DeepMimic hand and foot
paths) run on this follower as the installation builds it for a puck, unless said otherwise.

- Size and offset (``invariance``, "scale" for pucks and touches, "none" by default): a
  performance is taken relative to where its gesture began (the *anchor*) and divided, per
  template, by a size estimated as the gesture unfolds (as GVF follows scale): the least-squares
  ratio between the performance and the template's states at the followed progress, both
  relative to their starts, with a prior of ``scale_prior`` samples at 1, within
  ``scale_range``. The paper's model is unchanged (one Gaussian state per template sample); only
  its input is mapped. Gestures at 0.7-1.4x: valid 0.70 of the time after 30% of them with
  features as recorded, 0.90-0.92 with "scale"; progress RMSE median 0.037 -> 0.021. The
  estimate and the progress can feed each other on a template with no still start (a generic
  stream sped up 2x was lost at 45% in one case of six), hence "none" for streams.
- Probabilities: each template's evidence is its sum of per-step log-likelihoods of the *raw*
  sample (its own scale and the estimated size enter as the Gaussian's Jacobian, so templates of
  different sizes compare fairly), forgotten with time constant ``memory`` samples; a softmax
  gives probabilities summing to 1. ``best`` changes only when another template leads by
  ``switch_margin`` nats, and drives only while at least ``min_probability`` likely.
- Refusal (null rejection), per template against its own spread (:mod:`behaviors.mop.hmm`):
  per-step log-likelihoods forgotten with ``null_memory`` samples, read as an RMS distance in
  ``sigma`` units. Beyond ``null_distance`` the template is refused; it is accepted again below
  ``accept_distance`` (hysteresis, not a permanent latch: with the bird alone in
  ``tests/mop/test_live.py`` the latch and the hysteresis took the same 3 of 17 other gestures
  at 60% with one spread per template, and the hysteresis takes 0 with one per column).
  Tighter limits did not separate unrelated motion from true performances: null 1.4 / accept
  1.05 cut true validity after 30% from 0.90 to 0.75 while unrelated motion stayed 0.55-0.62
  valid; 1.1 / 0.85: 0.65 and 0.51.
- Engagement: a template drives nothing until its progress passed its onset (the first state
  ``onset`` sigmas from its first state) *and* the input itself left the anchor by as much: a
  still input lets the transitions' prior drift along the first states (a still tail after a
  diagonal line re-engaged the circle within 6 samples). Valid = ``best`` engaged, not refused,
  its spread at most ``max_spread`` (in states), for ``confirm`` samples in a row.
- Spotting in a continuous stream: once ``best`` reached ``end`` progress while valid, the
  gesture ends when the input rests or moves on from where it ended (by ``accept_distance``; the
  onset alone was crossed by noise) or stops matching; the next gesture is anchored where the
  last one ended, and forward, evidence and sizes start afresh. A valid action resting at 90%
  or more has ended too. When every template has been refused for ``lost_samples`` samples the
  attempt is abandoned and a new one starts at the current sample. While nothing is engaged and
  the input is still (``still_samples`` within a quarter of the onset), the anchor follows it.
  Back to back, the median gesture is recognised at 24% of it (before: never, for 53% of them
  among the six example gestures; among 20 templates median 43% -> 24%, never 22% -> 16%).
- Direction (``tangent``, 0 by default): each state also holds its direction of motion. It
  raised validity after 30% at 0.7-1.4x to 0.95 and at 0.6x/1.5x from 0.53 to 0.80, and halved
  the raise-hold-return error, but a performer going back along the path is refused after about
  0.2 s (``tests/mop/test_plugin.py``), so it is an option.
- A non-finite sample (a lost input) changes nothing: the previous state is returned, invalid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from behaviors.mop.forward import WindowedForward
from behaviors.mop.hmm import TemplateBank, TemplateError, Transitions, build_bank
from tabletop.frames import InputError

__all__ = ["ActionFollower", "FollowerGroup", "FollowState", "TemplateError", "SampleError"]

INVARIANCES = ("scale", "offset", "none")
#: Samples over which the direction of motion is measured (template and performance alike).
TANGENT_LAG = 2


class SampleError(InputError):
    """A live sample has the wrong shape for the template set."""


@dataclass(frozen=True)
class FollowState:
    """The follower's answer after one sample.

    ``best``: the most probable template; ``progress`` (0..1) and ``variance`` (progress units
    squared) of ``best``; ``probabilities``: per template, summing to 1; ``progress_by``: per
    template; ``valid``: the performance matches ``best`` well enough to drive a character;
    ``loglik``: recent mean per-sample log-likelihood of ``best`` (its own units);
    ``distance``: that log-likelihood as an RMS distance in ``sigma`` units per feature;
    ``restarted``: a new performance of ``best`` began at this sample; ``likely``: while a
    gesture unfolds, the templates not refused, likeliest first, as (name, probability,
    progress): early feedback, whether or not anything is valid yet; ``scale_by``: each
    template's estimated performance size (1 = as recorded); ``holding``: ``best`` is where its
    template holds still (or at its end), so a performer resting there is holding the action.
    """

    best: str
    progress: float
    variance: float
    probabilities: dict[str, float]
    progress_by: dict[str, float]
    valid: bool
    loglik: float
    distance: float = 0.0
    restarted: bool = False
    loglik_by: dict[str, float] = field(default_factory=dict)
    likely: tuple[tuple[str, float, float], ...] = ()
    scale_by: dict[str, float] = field(default_factory=dict)
    holding: bool = False


class ActionFollower:
    """Follows the progress of a live performance along several action templates at once.

    ``templates``: name -> (n_i, d) samples, regularly spaced at the rate the follower is stepped.
    ``sigma``: observation spread in units of each template's own spread; ``window``: p, the
    half-width of the forward window in states (reach only); ``transitions``: forward weights
    (self, next, skips...); ``backward``: weight of moving one state back; ``restart``:
    probability per step that a new performance starts; ``memory``: forgetting of the evidence
    in samples; ``units`` (d,): the features' units (what makes columns comparable), default
    the pooled spread of each column; ``min_scale`` (d,): floor of every template's scale in the
    features' own units (the input's noise); ``hold_tolerance``: see :mod:`behaviors.mop.hmm`;
    ``still_samples``, ``lost_samples``, ``end``: spotting (samples, samples, progress); the
    rest: see the module docstring.
    """

    def __init__(self, templates: Mapping[str, np.ndarray], *, sigma: float = 0.2, window: int = 15,
                 transitions: tuple[float, ...] = (0.3, 0.35, 0.25, 0.1), backward: float = 0.1,
                 restart: float = 1e-4, memory: float = 20.0, null_distance: float = 1.8,
                 max_spread: float = 0.15, relative_floor: float = 0.05, floor: float = 1e-8,
                 min_scale: np.ndarray | None = None, null_memory: float = 16.0,
                 onset: float = 0.5, accept_distance: float = 1.2, invariance: str = "none", spotting: bool = True,
                 scale_range: tuple[float, float] = (0.55, 1.8), scale_prior: float = 3.0,
                 units: np.ndarray | None = None, hold_tolerance: float = 0.02,
                 switch_margin: float = 1.0, confirm: int = 2, end: float = 0.97,
                 still_samples: int = 6, min_probability: float = 0.6,
                 tangent: float = 0.0, lost_samples: int = 6) -> None:
        for name, v, ok in (("sigma", sigma, sigma > 0), ("window", window, window >= 1),
                            ("memory", memory, memory >= 1), ("null_distance", null_distance, null_distance > 0),
                            ("null_memory", null_memory, null_memory >= 1),
                            ("onset", onset, onset >= 0),
                            ("accept_distance", accept_distance, 0 < accept_distance <= null_distance),
                            ("max_spread", max_spread, max_spread > 0),
                            ("relative_floor", relative_floor, relative_floor >= 0),
                            ("floor", floor, floor >= 0), ("scale_prior", scale_prior, scale_prior > 0),
                            ("hold_tolerance", hold_tolerance, hold_tolerance >= 0),
                            ("switch_margin", switch_margin, switch_margin >= 0),
                            ("confirm", confirm, confirm >= 1), ("end", end, 0 < end <= 1),
                            ("still_samples", still_samples, still_samples >= 2),
                            ("min_probability", min_probability, 0 <= min_probability < 1),
                            ("tangent", tangent, tangent >= 0)):
            if not (math.isfinite(v) and ok):
                raise TemplateError(f"follower parameter {name} = {v} is out of range")
        if invariance not in INVARIANCES:
            raise TemplateError(f"follower invariance {invariance!r}: choose from {', '.join(INVARIANCES)}")
        lo, hi = (float(v) for v in scale_range)
        if not (0 < lo <= 1 <= hi and math.isfinite(hi)):
            raise TemplateError(f"follower scale_range {list(scale_range)} must hold 1, e.g. [0.55, 1.8]")
        self.bank = build_bank(templates, relative_floor, min_scale, units, hold_tolerance)
        self.names: tuple[str, ...] = self.bank.names
        self.sigma = float(sigma)
        self.memory = float(memory)
        self.null_distance = float(null_distance)
        self.max_spread = float(max_spread)
        self.invariance = invariance
        self.spotting = bool(spotting)
        self.scale_range = (lo, hi)
        self.confirm, self.end, self.switch_margin = int(confirm), float(end), float(switch_margin)
        self.still_samples = int(still_samples)
        self.min_probability = float(min_probability)
        self.lost_samples = int(lost_samples)
        self.tangent = float(tangent)
        self._fbank = self._with_tangents(templates)
        self._zdim = int(self._fbank.means.shape[1])
        self.forward = WindowedForward(self._fbank, sigma=sigma, half_window=int(window),
                                       transitions=Transitions(tuple(transitions), backward, restart),
                                       floor=floor)
        self._decay = 1.0 - 1.0 / self.memory
        self.null_memory = float(null_memory)
        self._null2 = self.null_distance ** 2
        self._accept2 = float(accept_distance) ** 2
        self.onset = float(onset)
        self._params = dict(sigma=float(sigma), window=int(window), transitions=tuple(transitions),
                            backward=float(backward), restart=float(restart), memory=float(memory),
                            null_distance=float(null_distance), max_spread=float(max_spread),
                            floor=float(floor), null_memory=float(null_memory), onset=float(onset))
        self._null_decay = 1.0 - 1.0 / self.null_memory
        self._log_constant = self.log_constant
        b = self.bank
        self._onset_state = self._onset_states()
        self._jacobian = np.log(b.scale).sum(axis=1)            # (K,) log |d z / d x|
        self._units = b.units
        self._first_z = (b.first - b.center) / b.scale           # (K, d)
        # template states relative to their first, in units (for the size estimate)
        self._rel = np.concatenate([(b.template(k) * b.scale[k] + b.center[k] - b.first[k]) / self._units
                                    for k in range(len(self.names))])
        rho2 = np.mean((b.scale / self._units) ** 2, axis=1) * self.dim
        self._prior = float(scale_prior) * rho2                   # (K,) prior weight at size 1
        # the still radius (raw units): half the onset in the smallest spread of each column (a
        # radius in RMS spread made a slow start look still: the anchor crept along a 0.7x
        # circle's first samples, valid 0.17 of the time after 30% of it instead of 0.93)
        self._still_radius = 0.5 * max(self.onset, 0.1) * self.sigma * b.scale.min(axis=0)
        self.reset()

    def _with_tangents(self, templates: Mapping[str, np.ndarray]) -> TemplateBank:
        """The bank the forward algorithm runs on: each state's features followed, when
        ``tangent`` > 0, by its direction of motion (``tangent`` x the unit velocity over
        :data:`TANGENT_LAG` samples in the template's own units, shrinking to 0 below a quarter of
        the template's median speed, so holds have none). Direction is blind to tempo and size,
        and tells a raise from the return along the same path, a circle from a line through its
        arc and a gesture from its mirror image."""
        b = self.bank
        if self.tangent <= 0:
            return b
        k = len(b.names)
        self._v0 = np.zeros(k)
        parts = []
        for i, a in enumerate(np.asarray(templates[n], dtype=float).reshape(len(templates[n]), -1)
                              for n in b.names):
            v = (a - a[np.maximum(np.arange(len(a)) - TANGENT_LAG, 0)]) / b.scale[i]
            speed = np.sqrt(np.sum(v * v, axis=1))
            moving = speed[speed > 1e-9]
            self._v0[i] = 0.25 * float(np.median(moving)) if moving.size else 1.0
            t = v / np.maximum(speed, self._v0[i])[:, None]
            keep = np.rint(b.source[b.starts[i]:b.starts[i] + b.lengths[i]] * (len(a) - 1)).astype(int)
            parts.append(np.hstack([b.template(i), self.tangent * t[keep]]))
        return TemplateBank(b.names, np.ascontiguousarray(np.concatenate(parts)), b.starts,
                            b.lengths, b.center, b.scale, b.first, b.source, b.units, b.holds)

    def _onset_states(self) -> np.ndarray:
        """Per template, the first state at least ``onset`` sigmas (RMS per feature) from its first
        state, or its farthest state when none is (state index)."""
        out = np.zeros(len(self.names))
        for k in range(len(self.names)):
            states = self.bank.template(k)
            d = np.sqrt(np.mean((states - states[0]) ** 2, axis=1)) / self.sigma
            far = np.flatnonzero(d >= self.onset)
            out[k] = far[0] if far.size else int(np.argmax(d))
        return out

    @property
    def dim(self) -> int:
        """Number of features per sample."""
        return self.bank.dim

    def reset(self) -> None:
        """Forget the performance; every template waits at its first state."""
        self.forward.reset()
        self._forget()
        self._state = None
        self._anchor: np.ndarray | None = None
        self._recent_x: list[np.ndarray] = []
        self._lag: list[np.ndarray] = []
        self._ended = -1

    def _forget(self) -> None:
        """Forget the evidence, sizes and validity of every template (not the forward state)."""
        if not hasattr(self, "_evidence"):   # allocated once: a group holds views of them
            k = len(self.names)
            self._evidence, self._recent, self._recent_weight = np.zeros(k), np.zeros(k), np.zeros(k)
            self._refused, self._engaged = np.zeros(k, dtype=bool), np.zeros(k, dtype=bool)
            self._entries = np.zeros(k, dtype=np.int64)
            self._num, self._den, self._size = np.zeros(k), np.zeros(k), np.ones(k)
        for a in (self._evidence, self._recent, self._recent_weight, self._refused, self._engaged,
                  self._entries, self._num, self._den):
            a.fill(0)
        self._size.fill(1.0)
        self._best = 0
        self._run = 0
        self._lost = 0
        self._end_x: np.ndarray | None = None
        self._state: FollowState | None = None

    @property
    def log_constant(self) -> float:
        """The Gaussian's normalising term ``-d log sigma - d/2 log 2 pi`` in every log-likelihood."""
        return -self._zdim * math.log(self.sigma) - 0.5 * self._zdim * math.log(2.0 * math.pi)

    def distance_of(self, loglik: float) -> float:
        """A mean per-sample log-likelihood as an RMS distance in ``sigma`` units per feature."""
        return math.sqrt(max(0.0, -2.0 * (loglik - self._log_constant) / self._zdim))

    def _idle_state(self) -> FollowState:
        k = len(self.names)
        far = 2.0 * self.null_distance
        loglik = self._log_constant - 0.5 * self._zdim * far * far
        return FollowState(self.names[0], 0.0, 0.0, {n: 1.0 / k for n in self.names},
                           {n: 0.0 for n in self.names}, False, loglik, far, False,
                           {n: loglik for n in self.names})

    def _sample(self, x: np.ndarray) -> np.ndarray | None:
        """x as floats of the templates' shape, or None when it holds a non-finite value."""
        x = np.asarray(x, dtype=float)
        if x.shape != (self.dim,):
            raise SampleError(
                f"sample has shape {x.shape}, expected ({self.dim},) like the templates' features")
        return x if math.isfinite(x.sum()) else None

    def _held(self) -> FollowState:
        """A lost sample: the previous state, marked invalid."""
        held = self._state or self._idle_state()
        self._state = FollowState(held.best, held.progress, held.variance, held.probabilities,
                                  held.progress_by, False, held.loglik, held.distance, False,
                                  held.loglik_by, held.likely, held.scale_by, held.holding)
        return self._state

    def _inputs(self, x: np.ndarray) -> np.ndarray:
        """The sample in every template's standardised units (K, d): relative to the anchor and
        divided by the template's estimated size (see ``invariance``)."""
        b = self.bank
        if self._anchor is None:
            self._anchor = x.copy()
        if self.invariance == "none":
            z = (x - b.center) / b.scale
        else:
            r = (x - self._anchor)[None, :]
            if self.invariance == "scale":
                r = r / self._size[:, None]
            z = r / b.scale + self._first_z
        if self.tangent <= 0:
            return z
        lag = self._lag
        v = (x - (lag[0] if len(lag) == TANGENT_LAG else lag[-1] if lag else x))[None, :] / b.scale
        lag.append(x)
        if len(lag) > TANGENT_LAG:
            del lag[0]
        if self.invariance == "scale":
            v = v / self._size[:, None]
        speed = np.sqrt(np.sum(v * v, axis=1))
        t = v / np.maximum(speed, self._v0)[:, None]
        return np.hstack([np.broadcast_to(z, t.shape), self.tangent * t])

    def step(self, x: np.ndarray) -> FollowState:
        """Follow one live sample x (d,) in the templates' units; causal."""
        x = self._sample(x)
        if x is None:
            return self._held()
        fw = self.forward
        step_ll = fw.step(self._inputs(x))
        return self._finish(step_ll, fw, 0, fw.entries, x)

    def _restart_here(self, x: np.ndarray, forward: WindowedForward, offset: int,
                      still: bool = False) -> None:
        """A new attempt starts at this sample (``still``: at the mean of the still input):
        anchor there, every template at its first state, no evidence."""
        forward.reset_templates(offset + np.arange(len(self.names)))
        entries = self._entries.copy()
        self._forget()
        self._entries[:] = entries
        if still:
            self._anchor = np.mean(self._recent_x, axis=0)
        else:
            self._anchor = x.copy()
            self._recent_x = [x]

    def _displacement(self, x: np.ndarray) -> np.ndarray:
        """RMS distance (K,) of x from the anchor in each template's units (and size)."""
        if self._anchor is None:
            return np.full(len(self.names), np.inf)
        r = (x - self._anchor)[None, :] / self.bank.scale
        if self.invariance == "scale":
            r = r / self._size[:, None]
        return np.sqrt(np.mean(r * r, axis=1))

    def _departed(self, x: np.ndarray, k: int) -> bool:
        """The input left the point where template ``k`` reached its end by the acceptance
        distance (the onset alone was crossed by noise: 0.1 of the spread per column)."""
        r = (x - self._end_x) / (self.bank.scale[k] * self._size[k])
        return bool(np.mean(r * r) >= self._accept2 * self.sigma ** 2)

    def _still(self, x: np.ndarray) -> bool:
        """The input stayed within the still radius for ``still_samples`` samples."""
        buf = self._recent_x
        buf.append(x)
        if len(buf) > self.still_samples:
            del buf[0]
        if len(buf) < self.still_samples:
            return False
        a = np.array(buf)
        return bool(((a.max(axis=0) - a.min(axis=0)) <= 2.0 * self._still_radius).all())

    def _finish(self, step_ll: np.ndarray, forward: WindowedForward, offset: int,
                entries: np.ndarray, x: np.ndarray) -> FollowState:
        """Evidence, probabilities, best, validity and spotting from one forward step's
        per-template log-likelihoods; this follower's templates are ``forward``'s from
        ``offset`` on."""
        k = len(self.names)
        b = self.bank
        mean = forward.mean[offset:offset + k]
        g = b.starts + np.minimum(mean, b.lengths - 1.0)
        gi = np.minimum(g.astype(np.intp), b.starts + b.lengths - 2)
        frac = g - gi
        src = b.source
        progress = src[gi] + frac * (src[gi + 1] - src[gi])
        # size: least squares between the performance and the followed states (both relative)
        if self.invariance == "scale" and self._anchor is not None:
            q = self._rel[gi] + frac[:, None] * (self._rel[gi + 1] - self._rel[gi])
            r = (x - self._anchor) / self._units
            self._num += q @ r
            self._den += np.einsum("kd,kd->k", q, q)
            lo, hi = self.scale_range
            np.clip((self._num + self._prior) / (self._den + self._prior), lo, hi, out=self._size)
        raw_ll = step_ll - self._jacobian
        if self.invariance == "scale":
            raw_ll = raw_ll - self.dim * np.log(self._size)
        self._evidence *= self._decay
        self._evidence += raw_ll
        self._recent *= self._null_decay
        self._recent += step_ll
        self._recent_weight *= self._null_decay
        self._recent_weight += 1.0
        new = entries > self._entries   # re-entered: a new performance, judged afresh
        self._entries[:] = entries
        # a refused template whose performance is back at its start, matching it, may begin
        # anew (re-entry is not counted while the main window already holds the first states)
        back = self._refused & (mean < self._onset_state)
        if np.count_nonzero(back):
            back &= (self._log_constant - step_ll) * (2.0 / self._zdim) <= self._null2
            new |= back
        if np.count_nonzero(new):
            self._recent[new] = self._log_constant
            self._recent_weight[new] = 1.0
            self._refused[new] = False
            self._engaged[new] = False
        mean_ll = self._recent / self._recent_weight
        dist2 = (self._log_constant - mean_ll) * (2.0 / self._zdim)
        self._refused |= dist2 > self._null2
        self._refused &= ~(dist2 < self._accept2)
        # engaged once past the onset state *and* the input itself has left the anchor by the
        # onset (template units): a still input lets the prior drift along the first states
        # (measured: a still tail after a diagonal re-engaged the circle within 6 samples)
        past = (mean >= self._onset_state) & ~self._refused
        if np.count_nonzero(past & ~self._engaged):
            # averaged over the last samples: single jitter spikes crossed the onset of a
            # template with a narrow column (a still puck took the line's end, 29% of the time)
            r = self._displacement(np.mean(self._recent_x[-3:] + [x], axis=0))
            past &= r >= self.onset * self.sigma
        self._engaged |= past
        top = int(np.argmax(self._evidence))
        p = np.exp(self._evidence - self._evidence[top])
        p /= p.sum()
        return self._conclude(top, p, progress, g, gi, mean_ll, new, step_ll, forward, offset, x,
                              (progress.tolist(), p.tolist(), mean_ll.tolist(), self._size.tolist()))

    def _conclude(self, top: int, p: np.ndarray, progress: np.ndarray, g: np.ndarray,
                  gi: np.ndarray, mean_ll: np.ndarray, new: np.ndarray, step_ll: np.ndarray,
                  forward: WindowedForward, offset: int, x: np.ndarray,
                  lists: tuple[list, list, list, list]) -> FollowState:
        """The rest of :meth:`_finish` once the per-template arrays are updated (a group updates
        them for all its followers at once): best, validity, the state and spotting. ``top``:
        the template of most evidence; ``p``: probabilities; ``lists``: progress, ``p``,
        ``mean_ll`` and sizes as lists (for the state's dictionaries)."""
        b = self.bank
        src = b.source
        if self._evidence[top] - self._evidence[self._best] > self.switch_margin or self._refused[self._best]:
            self._best = top
        bi = self._best
        progress_list, p_list, mean_ll_list, size_list = lists
        engaged = bool(self._engaged.any())
        slope = src[gi[bi] + 1] - src[gi[bi]]
        var = forward.var_of(offset + bi)
        variance = var * slope * slope
        # the spread limit counts states, not the progress a compressed hold spans
        spread2 = var / (b.lengths[bi] - 1.0) ** 2
        ok = bool(self._engaged[bi] and not self._refused[bi] and spread2 <= self.max_spread ** 2
                  and p_list[bi] >= self.min_probability)
        self._run = self._run + 1 if ok else 0
        valid = self._run >= self.confirm
        loglik = mean_ll_list[bi]
        names = self.names
        still = self._still(x)
        likely: tuple[tuple[str, float, float], ...] = ()
        if engaged or (not still and self._displacement(x).max() >= self.onset * self.sigma):
            order = [i for i in np.argsort(-p)[:3] if not self._refused[i]]
            likely = tuple((names[i], p_list[i], progress_list[i]) for i in order)
        progress_by = dict(zip(names, progress_list))
        best, best_progress = names[bi], progress_list[bi]
        if self._ended >= 0 and not engaged:
            # the last gesture ended and no new one has begun: it stays at its end, not driving
            best, best_progress = names[self._ended], 1.0
            progress_by[best] = 1.0
        state = self._state = FollowState(
            best=best, progress=best_progress, variance=variance,
            probabilities=dict(zip(names, p_list)), progress_by=progress_by,
            valid=valid, loglik=loglik, distance=self.distance_of(loglik), restarted=bool(new[bi]),
            loglik_by=dict(zip(names, mean_ll_list)), likely=likely,
            scale_by=dict(zip(names, size_list)),
            holding=bool(b.holds[int(round(g[bi]))] or progress_list[bi] >= 0.9))
        if engaged:
            self._ended = -1
        # spotting: the gesture ended (its end reached, or it rests near its end), or every
        # template refused it: start afresh here; a still input waiting for a gesture anchors it
        if self.invariance != "none":
            if valid and progress_list[bi] >= self.end and self._end_x is None:
                self._end_x = x.copy()
            step_d2 = (self._log_constant - step_ll[bi]) * (2.0 / self._zdim)
            self._lost = self._lost + 1 if bool(self._refused.all()) else 0
            if self._end_x is not None and (still or step_d2 > self._null2 or not ok or
                                            self._departed(x, bi)):
                # the end was reached and the performer rests there or moves on: a new gesture
                # starts where the last one ended
                end_x = self._end_x
                self._restart_here(x, forward, offset)
                self._anchor = end_x
                self._ended = bi
            elif valid and still and progress_list[bi] >= 0.9:
                self._restart_here(x, forward, offset)
                self._ended = bi
            elif self._lost >= self.lost_samples:
                self._restart_here(x, forward, offset)
            elif still and not engaged:
                self._restart_here(x, forward, offset, still=True)
        self._state = state
        return state

    def same_parameters(self, other: "ActionFollower") -> bool:
        """True when ``other`` follows with the same parameters (its templates may differ)."""
        return self._params == other._params


from behaviors.mop.group import FollowerGroup  # noqa: E402  (re-exported: one import for both)
