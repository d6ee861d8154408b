"""Follow and recognise several actions at once (MOP section 3.2 with several templates).

:class:`ActionFollower` standardises live samples with the template set's pooled scale, advances
the windowed forward algorithm of every template by one sample, and reports for the most probable
template its progress (0..1), variance and mean per-sample log-likelihood, plus every template's
probability and progress.

- Probabilities: each template's evidence is its sum of per-step log-likelihoods with
  exponential forgetting (time constant ``memory`` samples); a softmax across templates turns
  it into probabilities that sum to 1 and change smoothly, yet let a new action take over.
- Validity (null rejection), per template: its per-step log-likelihoods, forgotten with time
  constant ``null_memory`` samples, are converted into an RMS distance between the performance
  and the template in ``sigma`` units per feature. A template farther than ``null_distance`` is
  *refused* until it re-enters (a new performance of it begins) or the follower is reset: a
  performance that once left the template is not that action, even where it later crosses it.
  A template is *engaged* once its progress passed its onset, the first state ``onset`` sigmas
  (RMS) away from its first state: until the performance has left the start that every gesture
  shares, it is evidence of nothing. The output is valid while ``best`` is engaged, not refused,
  and its progress spread (standard deviation, 0..1 units) is at most ``max_spread``.
- Re-entry: every template can restart at its first state (see :mod:`behaviors.mop.forward`);
  ``FollowState.restarted`` is True on the step a new performance of ``best`` began.

Why refuse and engage, measured on ``examples/mop.yaml``'s scripted performers with only the bird
(one action, wave) on its puck, so that nothing but the likelihood can refuse the puck's four
other gestures and its slides home (``tests/mop/test_live.py``, 120 s, seeds 0-2): with the
plain validity rule (a 20-sample mean distance of ``best`` at most 2.0, nothing latched) the bird
took 90% of the lines, 46% of the zigzags and 35% of each slide home for its wave, and a puck at
rest was "waving" at progress 0. The distance of a line performed as a wave peaks at 2.5-3.3 but
averages 1.8, so averaging hides it: refusing as soon as the recent distance exceeds the limit,
and holding the refusal, takes the other gestures at 60% of them down to 0 of 60, and the bird
is driven 4-8% of the time while a gesture not its own is performed (the first part of a zigzag
or a line looks like a wave). The memory (16 samples, about 0.5 s at 30 Hz) and the limit (1.8)
trade that against a true performance going back faster than the model's one state per step,
whose lag reaches a distance of 2.0 over 8 samples (``tests/mop/test_plugin.py``, going back at
1.4x): memory 8 with limit 2.0 refused it; limit 2.5 (memory 4 or 8) let the bird take 29-47% of
the other gestures at 60%, memory 12 with limit 2.0 up to 12%. The onset (0.5 sigma) removes the
slides home (35% -> 0%): every template starts still, so any motion at all matches its first
states. A refused template whose performance is back at its start (progress below its onset,
this step within the limit) begins anew: re-entry is not counted while the main window still
holds the first states, and without this a performer that never rests (a mocap stream) had
every template refused for good after the first unknown motion (15 of 51 gestures recognised).
- A non-finite sample (a lost input) changes nothing: the previous state is returned, invalid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from behaviors.mop.forward import WindowedForward
from behaviors.mop.hmm import TemplateBank, TemplateError, Transitions, build_bank
from tabletop.frames import InputError

__all__ = ["ActionFollower", "FollowerGroup", "FollowState", "TemplateError", "SampleError"]


class SampleError(InputError):
    """A live sample has the wrong shape for the template set."""


@dataclass(frozen=True)
class FollowState:
    """The follower's answer after one sample.

    ``best``: the most probable template; ``progress`` (0..1) and ``variance`` (progress units
    squared) of ``best``; ``probabilities``: per template, summing to 1; ``progress_by``: per
    template; ``valid``: the performance matches ``best`` well enough to drive a character;
    ``loglik``: recent mean per-sample log-likelihood of ``best`` (standardised features);
    ``distance``: that log-likelihood as an RMS distance in ``sigma`` units per feature;
    ``restarted``: a new performance of ``best`` began at this sample.
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


class ActionFollower:
    """Follows the progress of a live performance along several action templates at once.

    ``templates``: name -> (n_i, d) samples, regularly spaced at the rate the follower is stepped.
    ``sigma``: observation spread in units of the pooled per-feature scale; ``window``: p, the
    half-width of the forward window in states; ``transitions``: forward weights (self, next,
    skips...); ``backward``: weight of moving one state back; ``restart``: probability per step
    that a new performance starts; ``memory``: forgetting time constant of the evidence in
    samples; ``null_distance``, ``null_memory`` (samples), ``onset`` (sigmas) and ``max_spread``:
    validity (see the module docstring);
    ``relative_floor``: floor of the per-feature scale relative to the overall spread;
    ``min_scale``: optional (d,) floor of the per-feature scale in the features' own units (the
    input's noise, e.g. :attr:`behaviors.mop.features.PathFeatures.min_scale`).
    """

    def __init__(self, templates: Mapping[str, np.ndarray], *, sigma: float = 0.2, window: int = 15,
                 transitions: tuple[float, ...] = (0.3, 0.35, 0.25, 0.1), backward: float = 0.1,
                 restart: float = 1e-4, memory: float = 20.0, null_distance: float = 1.8,
                 max_spread: float = 0.15, relative_floor: float = 0.05, floor: float = 1e-8,
                 min_scale: np.ndarray | None = None, null_memory: float = 16.0,
                 onset: float = 0.5) -> None:
        for name, v, ok in (("sigma", sigma, sigma > 0), ("window", window, window >= 1),
                            ("memory", memory, memory >= 1), ("null_distance", null_distance, null_distance > 0),
                            ("null_memory", null_memory, null_memory >= 1),
                            ("onset", onset, onset >= 0),
                            ("max_spread", max_spread, max_spread > 0),
                            ("relative_floor", relative_floor, relative_floor >= 0),
                            ("floor", floor, floor >= 0)):
            if not (math.isfinite(v) and ok):
                raise TemplateError(f"follower parameter {name} = {v} is out of range")
        self.bank = build_bank(templates, relative_floor, min_scale)
        self.names: tuple[str, ...] = self.bank.names
        self.sigma = float(sigma)
        self.memory = float(memory)
        self.null_distance = float(null_distance)
        self.max_spread = float(max_spread)
        self.forward = WindowedForward(self.bank, sigma=sigma, half_window=int(window),
                                       transitions=Transitions(tuple(transitions), backward, restart),
                                       floor=floor)
        self._decay = 1.0 - 1.0 / self.memory
        self.null_memory = float(null_memory)
        self._null2 = self.null_distance ** 2
        self.onset = float(onset)
        self.onset_progress = self._onset_progress()
        self._null_decay = 1.0 - 1.0 / self.null_memory
        self._params = dict(sigma=float(sigma), window=int(window), transitions=tuple(transitions),
                            backward=float(backward), restart=float(restart), memory=float(memory),
                            null_distance=float(null_distance), max_spread=float(max_spread),
                            floor=float(floor), null_memory=float(null_memory),
                            onset=float(onset))
        self._log_constant = self.log_constant
        self._inv_span2 = (1.0 / (self.bank.lengths - 1.0) ** 2).tolist()
        self.reset()

    def _onset_progress(self) -> np.ndarray:
        """Per template, the progress (0..1) of its first state at least ``onset`` sigmas (RMS per
        feature) from its first state, or of its farthest state when none is."""
        out = np.zeros(len(self.names))
        for k in range(len(self.names)):
            states = self.bank.template(k)
            d = np.sqrt(np.mean((states - states[0]) ** 2, axis=1)) / self.sigma
            far = np.flatnonzero(d >= self.onset)
            out[k] = (far[0] if far.size else int(np.argmax(d))) / (len(states) - 1)
        return out

    @property
    def dim(self) -> int:
        """Number of features per sample."""
        return self.bank.dim

    def reset(self) -> None:
        """Forget the performance; every template waits at its first state."""
        self.forward.reset()
        self._forget()

    def _forget(self) -> None:
        """Forget the evidence and validity of every template (not the forward state)."""
        k = len(self.names)
        self._evidence = np.zeros(k)
        self._weight = 0.0
        self._recent = np.zeros(k)
        self._recent_weight = np.zeros(k)
        self._refused = np.zeros(k, dtype=bool)
        self._engaged = np.zeros(k, dtype=bool)
        self._entries = np.zeros(k, dtype=np.int64)
        self._state: FollowState | None = None

    @property
    def log_constant(self) -> float:
        """The Gaussian's normalising term ``-d log sigma - d/2 log 2 pi`` in every log-likelihood."""
        return -self.dim * math.log(self.sigma) - 0.5 * self.dim * math.log(2.0 * math.pi)

    def distance_of(self, loglik: float) -> float:
        """A mean per-sample log-likelihood as an RMS distance in ``sigma`` units per feature."""
        return math.sqrt(max(0.0, -2.0 * (loglik - self._log_constant) / self.dim))

    def _idle_state(self) -> FollowState:
        k = len(self.names)
        far = 2.0 * self.null_distance
        loglik = self._log_constant - 0.5 * self.dim * far * far
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
                                  held.loglik_by)
        return self._state

    def step(self, x: np.ndarray) -> FollowState:
        """Follow one live sample x (d,) in the templates' units; causal."""
        x = self._sample(x)
        if x is None:
            return self._held()
        fw = self.forward
        step_ll = fw.step((x - self.bank.center) / self.bank.scale)
        return self._finish(step_ll, fw.progress, fw, 0, fw.entries)

    def _finish(self, step_ll: np.ndarray, progress: np.ndarray, forward: WindowedForward,
                offset: int, entries: np.ndarray) -> FollowState:
        """Evidence, probabilities, best and validity from one forward step's per-template
        log-likelihoods, progress (0..1) and re-entry counts; this follower's templates are
        ``forward``'s from ``offset`` on."""
        self._evidence *= self._decay
        self._evidence += step_ll
        self._weight = self._decay * self._weight + 1.0
        self._recent *= self._null_decay
        self._recent += step_ll
        self._recent_weight *= self._null_decay
        self._recent_weight += 1.0
        new = entries > self._entries   # re-entered: a new performance, judged afresh (this
        self._entries[:] = entries      # step's likelihood still mostly belongs to the old one)
        # a refused template whose performance is back at its start, matching it, may begin anew
        # (re-entry is not counted when the main window already holds the first states)
        back = self._refused & (progress < self.onset_progress)
        if np.count_nonzero(back):
            back &= (self._log_constant - step_ll) * (2.0 / self.dim) <= self._null2
            new |= back
        if np.count_nonzero(new):
            self._recent[new] = self._log_constant
            self._recent_weight[new] = 1.0
            self._refused[new] = False
            self._engaged[new] = False
        mean_ll = self._recent / self._recent_weight
        # squared RMS distance per feature in sigma units, every template (see distance_of)
        dist2 = (self._log_constant - mean_ll) * (2.0 / self.dim)
        self._refused |= dist2 > self._null2
        self._engaged |= (progress >= self.onset_progress) & ~self._refused
        b = int(np.argmax(self._evidence))
        p = np.exp(self._evidence - self._evidence[b])
        p /= p.sum()
        names = self.names
        variance = forward.var_of(offset + b) * self._inv_span2[b]
        restarted = bool(new[b])
        loglik = float(mean_ll[b])
        dist = self.distance_of(loglik)
        valid = (self._engaged[b] and not self._refused[b] and variance <= self.max_spread ** 2)
        self._state = FollowState(
            best=names[b], progress=float(progress[b]), variance=variance,
            probabilities=dict(zip(names, p.tolist())), progress_by=dict(zip(names, progress.tolist())),
            valid=bool(valid), loglik=loglik, distance=dist, restarted=bool(restarted),
            loglik_by=dict(zip(names, mean_ll.tolist())))
        return self._state

    def same_parameters(self, other: "ActionFollower") -> bool:
        """True when ``other`` follows with the same parameters (its templates may differ)."""
        return self._params == other._params


class FollowerGroup:
    """Several followers (one per performer or character, each with its own templates and
    input) stepped together in one vectorised forward pass: one tick of many characters costs
    about as much as one follower over all their templates. The followers must share their
    parameters; their feature counts may differ. Each keeps its own state (``step`` of the
    group and of a member must not be mixed).
    """

    def __init__(self, followers: Sequence[ActionFollower]) -> None:
        self.followers = list(followers)
        if not self.followers:
            raise TemplateError("a follower group needs at least one follower")
        first = self.followers[0]
        for i, f in enumerate(self.followers[1:], 1):
            if not first.same_parameters(f):
                raise TemplateError(f"follower {i} of the group has other parameters than follower 0; "
                                    "a group's followers must share sigma, window, transitions and limits")
        width = max(f.dim for f in self.followers)
        means, starts, lengths, dims, names, owner = [], [], [], [], [], []
        offset = 0
        for i, f in enumerate(self.followers):
            b = f.bank
            padded = np.zeros((b.means.shape[0], width))
            padded[:, :b.dim] = b.means
            means.append(padded)
            starts.append(b.starts + offset)
            offset += b.means.shape[0]
            lengths.append(b.lengths)
            dims += [b.dim] * len(b.names)
            names += [f"{i}:{n}" for n in b.names]
            owner += [i] * len(b.names)
        bank = TemplateBank(tuple(names), np.concatenate(means), np.concatenate(starts),
                            np.concatenate(lengths), np.zeros(width), np.ones(width))
        p = first._params
        self.forward = WindowedForward(bank, sigma=p["sigma"], half_window=p["window"],
                                       transitions=first.forward.transitions, floor=p["floor"],
                                       dims=np.array(dims))
        self._owner = np.array(owner, dtype=np.intp)
        bounds = np.concatenate([[0], np.cumsum([len(f.names) for f in self.followers])])
        self._slices = [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]
        self._z = np.zeros((len(self.followers), width))
        self.reset()

    def reset(self) -> None:
        """Forget every performance."""
        self.forward.reset()
        for f in self.followers:
            f.reset()

    def reset_member(self, i: int) -> None:
        """Forget the performance followed by member ``i`` only (its next performance starts
        afresh: every template at its first state, no evidence); the others go on."""
        sl = self._slices[i]
        self.forward.reset_templates(np.arange(sl.start, sl.stop))
        f = self.followers[i]
        f._forget()
        f._entries[:] = self.forward.entries[sl]

    def step(self, samples: Sequence[np.ndarray]) -> list[FollowState]:
        """One sample per follower, in order; returns each follower's state."""
        if len(samples) != len(self.followers):
            raise SampleError(f"{len(samples)} samples for a group of {len(self.followers)} followers")
        lost = []
        for i, (f, x) in enumerate(zip(self.followers, samples)):
            x = f._sample(x)
            if x is None:
                lost.append(i)
            else:
                self._z[i, :f.dim] = (x - f.bank.center) / f.bank.scale
        fw = self.forward
        saved = None
        if lost:
            saved = fw.snapshot(np.flatnonzero(np.isin(self._owner, lost)))
        step_ll = fw.step(self._z[self._owner])
        if saved is not None:
            fw.restore(saved)
        progress = fw.progress
        out = []
        for i, (f, sl) in enumerate(zip(self.followers, self._slices)):
            if i in lost:
                out.append(f._held())
            else:
                out.append(f._finish(step_ll[sl], progress[sl], fw, sl.start, fw.entries[sl]))
        return out
