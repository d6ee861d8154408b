"""Follow, recognise and spot several actions at once (MOP section 3.2 with several templates).

:class:`ActionFollower` maps each live sample into every template's own units
(:mod:`behaviors.mop.invariance`), advances the windowed forward algorithm of every template by
one sample (:mod:`behaviors.mop.forward`), and reports for the most probable template its
progress (0..1), variance and mean per-sample log-likelihood, plus every template's probability
and progress (:class:`~behaviors.mop.state.FollowState`). Whether it may drive a character is
decided in :mod:`behaviors.mop.validity`, where gestures begin and end in
:mod:`behaviors.mop.spotting`. Figures come from ``bench/follow_quality.py`` (puck paths: six
drawn gestures and fourteen DeepMimic hand and foot paths) run on this follower as the
installation builds it for a puck, unless said otherwise. This module builds the follower (its
parameters, templates and state); each sample's evidence, probabilities, best and validity are
concluded in :mod:`behaviors.mop.recognition`.

- A non-finite sample (a lost input) changes nothing: the previous state is returned, invalid.
- A glitch (a marker misread for one frame, a mocap joint flipped) is held as lost too, counted
  in ``glitches``: a sample that jumped farther than any performer moves in a sample, or that
  left every likely template's path at once (:mod:`behaviors.mop.glitch`, its figures). Only
  one: a second in a row is a real departure and is followed.
"""

from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from behaviors.kernel_cache import load
from behaviors.mop import (glitch, halts, overrun, path_kernel, reversal, size_probe,
                           speed_profile, tempo, window_kernel)
from behaviors.mop.forward import WindowedForward
from behaviors.mop.glitch import (OFF_PATH, ON_PATH, REACH_AHEAD, REACH_BACK, glitch_limits,
                                  path_distance)
from behaviors.mop.holding import hold_maps
from behaviors.mop.hmm import HOLD_DWELL, TemplateError, Transitions, build_bank
from behaviors.mop.invariance import INVARIANCES, TANGENT_LAG, PerformanceFrame, template_velocities
from behaviors.mop.parameters import check_ranges
from behaviors.mop.recognition import Recognition
from behaviors.mop.refusal import Refusal, shape_limits
from behaviors.mop import commitment, coverage, fresh_refusal, member_spotting
from behaviors.mop.shape_lead import ShapeLead
from behaviors.mop.sharing import shared_until
from behaviors.mop.spotting import SHARE_SIZES, SHARE_SKIP, GestureSpotting
from behaviors.mop.stretch import state_stretches
from behaviors.mop.state import FollowState, SampleError
from behaviors.mop.turning import Turning
from behaviors.mop.follower_validity import Validity

__all__ = ["ActionFollower", "FollowState", "TemplateError", "SampleError"]

#: The compiled kernels a follower's step calls from Python, loaded when it is built, not on
#: the step that first calls one (behaviors.kernel_cache.load; what they call is in their code).
_KERNELS = (window_kernel.step_windows, window_kernel.seat_windows, glitch.path_distance,
            commitment.add_lagged_all, coverage.arc_ahead, path_kernel.nearest_on_paths,
            overrun.overruns, reversal.input_reversal, reversal.reversal_size,
            reversal.reversal_way, reversal.went_on, reversal.sizes_again,
            size_probe.probe_allowed, size_probe.take_probe, fresh_refusal.refuse,
            speed_profile.outpaces, speed_profile.turns_on, halts.halts, tempo.before_attempt,
            tempo.span, tempo.slow_take, member_spotting.lead_gain)


class ActionFollower(Recognition, PerformanceFrame, Validity, Refusal, Turning, GestureSpotting,
                     ShapeLead):
    """Follows the progress of a live performance along several action templates at once.

    ``templates``: name -> (n_i, d) samples, regularly spaced at the rate the follower is stepped.
    ``sigma``: observation spread in units of each template's own spread; ``window``: p, the
    half-width of the forward window in states (reach only); ``transitions``: forward weights
    (self, next, skips...); ``backward``: weight of moving one state back; ``restart``:
    probability per step that a new performance starts; ``memory``: forgetting of the evidence
    in samples; ``units`` (d,): the features' units (what makes columns comparable), default
    the pooled spread of each column; ``min_scale`` (d,): floor of every template's scale in the
    features' own units (the input's noise); ``still_scale`` (d,): floor of the spread the still
    radius is measured in (raw units; the radius is otherwise a share of the smallest template's
    spread per column, see :mod:`behaviors.mop.invariance`), which leaves every template's own
    tolerance as it is; ``hold_tolerance``: see :mod:`behaviors.mop.hmm`;
    ``still_samples``, ``lost_samples``, ``end``: spotting (samples, samples, progress);
    ``coverage`` (share of a template's path, the most asked), ``shape_distance``,
    ``shape_accept`` (sigma; default by ``invariance``, :func:`~behaviors.mop.refusal.
    shape_limits`) and ``shape_memory`` (samples): see :mod:`behaviors.mop.refusal`; ``dwell``: the
    share of a
    hold state's probability that stays each step (:func:`behaviors.mop.hmm.dwell_states`;
    default :data:`~behaviors.mop.hmm.HOLD_DWELL` with ``invariance``, else 0); the rest: see the
    module docstring.

    ``sigma`` is Eq. 1's sigma, which the paper takes as the standard deviation between measured
    and template data; each template here is one take, so no deviation between takes is there
    to measure, and sigma is a fixed share of each template's own spread, chosen on the tuned
    (not ``heldout_``) figures of ``python bench/follow_quality.py
    --sections=sized,unrelated,holds --sigma=S`` (the puck follower): valid after 30% at
    0.7-1.4x and at the 0.6/1.5x edges, progress RMSE median, hold RMSE max and valid share,
    unrelated valid share max (told: of no start) and mean:

    =====  =======  =====  =====  ========  =====  =========  =====  =====
    sigma  sized    edges  RMSE   h. RMSE   hold   unrelated  told   mean
    =====  =======  =====  =====  ========  =====  =========  =====  =====
    0.1    0.696    0.499  0.023  0.053     0.850  0.124      0.124  0.012
    0.15   0.889    0.689  0.021  0.053     0.946  0.076      0.056  0.013
    0.175  0.905    0.715  0.020  0.054     0.959  0.148      0.148  0.019
    0.2    0.916    0.759  0.019  0.055     0.958  0.068      0.068  0.015
    0.225  0.926    0.769  0.019  0.052     0.959  0.094      0.074  0.022
    0.25   0.917    0.778  0.019  0.053     0.959  0.198      0.198  0.025
    0.3    0.904    0.767  0.020  0.080     0.902  0.224      0.224  0.034
    =====  =======  =====  =====  ========  =====  =========  =====  =====

    0.2 is kept: narrower misses sized and held performances, wider lets unrelated motion
    drive (0.225 gains 0.01 on the sized shares at 0.094 unrelated, 0.015 -> 0.022 mean).
    The paper's measured deviation, taken on these templates at the true alignment (RMS per
    feature in each template's spread): tracking jitter alone 0.020 (median; at most 0.030),
    far under what follows well; a performer's redraw as ``bench/follow_shapes.py`` draws it,
    bent by 5% or 10% of its extent, 0.11 and 0.21, 1.1x or 1.2x taller, 0.11 and 0.22: 0.2
    is the deviation of a redraw at the larger of those.
    """

    def __init__(self, templates: Mapping[str, np.ndarray], *, sigma: float = 0.2, window: int = 15,
                 transitions: tuple[float, ...] = (0.3, 0.35, 0.25, 0.1), backward: float = 0.1,
                 restart: float = 1e-4, memory: float = 20.0, null_distance: float = 1.8,
                 max_spread: float = 0.15, relative_floor: float = 0.05, floor: float = 1e-8,
                 min_scale: np.ndarray | None = None, null_memory: float = 16.0,
                 onset: float = 0.5, accept_distance: float = 1.2, invariance: str = "none",
                 spotting: bool = True,
                 scale_range: tuple[float, float] = (0.55, 1.8), scale_prior: float = 3.0,
                 units: np.ndarray | None = None, hold_tolerance: float = 0.02,
                 switch_margin: float = 1.0, confirm: int = 2, end: float = 0.97,
                 still_samples: int = 6, min_probability: float = 0.6,
                 tangent: float = 0.0, lost_samples: int = 6, coverage: float = 0.08,
                 shape_distance: float | None = None, shape_accept: float | None = None,
                 shape_memory: float = 16.0, dwell: float | None = None,
                 threshold: float = 0.0, turn_limit: float = math.inf,
                 share_radius: float = 3.0, still_scale: np.ndarray | None = None) -> None:
        # as given: the defaults differ by invariance, which a group's members may mix
        load(*_KERNELS)   # before the first step (behaviors.kernel_cache)
        shape_given = (shape_distance, shape_accept)
        shape_distance, shape_accept = shape_limits(invariance, shape_distance, shape_accept)
        check_ranges(sigma=sigma, window=window, memory=memory, null_distance=null_distance,
                     null_memory=null_memory, onset=onset, accept_distance=accept_distance,
                     max_spread=max_spread, relative_floor=relative_floor, floor=floor,
                     scale_prior=scale_prior, hold_tolerance=hold_tolerance,
                     switch_margin=switch_margin, confirm=confirm, end=end,
                     still_samples=still_samples, min_probability=min_probability,
                     tangent=tangent, coverage=coverage, shape_distance=shape_distance,
                     shape_accept=shape_accept, shape_memory=shape_memory, dwell=dwell,
                     share_radius=share_radius, turn_limit=turn_limit, threshold=threshold)
        if invariance not in INVARIANCES:
            raise TemplateError(f"follower invariance {invariance!r}: "
                                f"choose from {', '.join(INVARIANCES)}")
        if dwell is None:   # features as recorded: a hold at another size is never reached
            dwell = HOLD_DWELL if invariance != "none" else 0.0
        lo, hi = (float(v) for v in scale_range)
        if not (0 < lo <= 1 <= hi and math.isfinite(hi)):
            raise TemplateError(f"follower scale_range {list(scale_range)} must hold 1, "
                                "e.g. [0.55, 1.8]")
        self.bank = build_bank(templates, relative_floor, min_scale, units, hold_tolerance)
        self.names: tuple[str, ...] = self.bank.names
        self._index = {n: i for i, n in enumerate(self.names)}
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
        self._tvel, self._v0 = template_velocities(templates, self.bank, TANGENT_LAG)
        self._fbank = self._with_tangents()
        self._zdim = int(self._fbank.means.shape[1])
        # the unit offset the overrun and speed-profile rules read: none for a follower alone
        # (a group member's is its columns'); made once, read only
        self._no_offset = np.zeros(self.bank.dim)
        moves = Transitions(tuple(transitions), backward, restart, float(dwell))
        fb = self._fbank   # its states stretched along fast stretches (behaviors.mop.stretch)
        self.forward = WindowedForward(fb, sigma=sigma, half_window=int(window),
                                       transitions=moves, floor=floor,
                                       stretch=state_stretches(fb.means, fb.starts, fb.lengths,
                                                               self.sigma))
        self._decay = 1.0 - 1.0 / self.memory
        self.null_memory = float(null_memory)
        self._null2 = self.null_distance ** 2
        self.accept_distance = float(accept_distance)
        self._accept2 = self.accept_distance ** 2
        self.onset = float(onset)
        # sigmas from the anchor a moving input must lie for the likeliest templates to be shown
        # before any is engaged (FollowState.likely); a stage that gates them by the input's
        # rest radius sets it lower (behaviors.mop.hints.HINT_ONSET)
        self.hint_onset = self.onset
        self._params = dict(sigma=float(sigma), window=int(window), transitions=tuple(transitions),
                            backward=float(backward), restart=float(restart), memory=float(memory),
                            null_distance=float(null_distance), max_spread=float(max_spread),
                            floor=float(floor), null_memory=float(null_memory), onset=float(onset),
                            coverage=float(coverage), shape_limits=shape_given,
                            shape_memory=float(shape_memory),
                            threshold=float(threshold), turn_limit=float(turn_limit),
                            share_radius=float(share_radius))
        self._null_decay = 1.0 - 1.0 / self.null_memory
        self._log_constant = self.log_constant
        b = self.bank
        self._onset_state = self._onset_states()
        # holds inside a template, where they dwell (behaviors.mop.holding)
        self._holds = hold_maps(b) if dwell > 0 else None
        self._still_scale = b.scale.min(axis=0)
        if still_scale is not None:
            floor = np.asarray(still_scale, dtype=float)
            if floor.shape != (b.dim,) or not np.all(np.isfinite(floor) & (floor >= 0)):
                raise TemplateError(f"still_scale must be {b.dim} non-negative numbers (one per "
                                    f"feature), got {np.asarray(still_scale).tolist()}")
            self._still_scale = np.maximum(self._still_scale, floor)
        self._setup_frame(float(scale_prior))
        self.coverage, self.shape_distance = float(coverage), float(shape_distance)
        self.shape_accept, self.shape_memory = float(shape_accept), float(shape_memory)
        # the threshold model: spatial inputs only (a noisy stream's own performance lost
        # against it: valid 0.72 instead of 0.95 of the time in tests/mop/test_follower.py), and
        # it sees positions only (off with direction features); off at infinity
        self.threshold = math.inf if tangent > 0 or invariance == "none" else float(threshold)
        self.turn_limit = float(turn_limit)
        self._setup_refusal()
        self.share_radius = float(share_radius)
        self._shared = None   # spotting._shares: off at 0 and for streams
        if self.share_radius > 0 and invariance != "none":
            lo_hi = hi / lo
            self._shared = shared_until(np.ascontiguousarray(self._rel * self._units),
                                        b.starts.astype(np.intp), b.lengths.astype(np.intp),
                                        np.geomspace(1.0 / lo_hi, lo_hi, SHARE_SIZES),
                                        np.ascontiguousarray(self.share_radius
                                                             * self._still_radius),
                                        SHARE_SKIP)
        self._setup_turning()
        self._jump = glitch_limits(templates, hi, self.sigma, b.scale)
        self.glitches = 0   # samples held as glitches (module docstring)
        # the squared path distances (glitch.path_distance) of a sample off every path and of
        # one on a path
        self._off_limit2 = OFF_PATH ** 2 * self.sigma ** 2 * float(self.dim)
        self._on_limit2 = ON_PATH ** 2 * self.sigma ** 2 * float(self.dim)
        self.reset()

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
        self._tempo_past: list[tuple[np.ndarray, np.ndarray]] = []   # (mean, x) per sample
        self._overran_k = -1   # the template that overran at the last sample (overrun.overruns)
        self._crawl, self._crawl_k = 0, -1   # samples in a row best crawled (tempo.crawls)
        self._lag: list[np.ndarray] = []
        self._ended = -1
        self._last_x: np.ndarray | None = None   # the last sample followed (_glitch)
        self._jumped = False   # the last finite sample was held as a glitch
        self._strayed = False   # the last sample followed lay off every path (glitch.ON_PATH)

    def _forget(self) -> None:
        """Forget the evidence, sizes and validity of every template (not the forward state)."""
        if not hasattr(self, "_evidence"):   # allocated once: a group holds views of them
            k = len(self.names)
            self._evidence, self._recent = np.zeros(k), np.zeros(k)
            self._recent_weight = np.zeros(k)
            self._refused, self._engaged = np.zeros(k, dtype=bool), np.zeros(k, dtype=bool)
            self._entries = np.zeros(k, dtype=np.int64)
            self._num, self._den, self._size = np.zeros(k), np.zeros(k), np.ones(k)
            self._least, self._judged = np.zeros(k), np.ones(k)
            self._at_hold_end = np.zeros(k, dtype=bool)
            self._fresh = np.zeros(k, dtype=bool)   # judged afresh (fresh_refusal)
            self._probe = np.zeros((k, 3))   # behaviors.mop.size_probe
            self._rev_undo = np.zeros(k)   # the last reversal's sizes in num (_reversal_sizes)
            self._rev_at = np.zeros(k)   # the landmark (state) its turn first met, -1: none
            self._seat = np.full(k, -1.0)   # a hold to follow from (holding.rested_sizes)
            self._seated = np.zeros(k, dtype=bool)   # seated on a hold in this attempt
        for a in (self._evidence, self._recent, self._recent_weight, self._refused, self._engaged,
                  self._entries, self._num, self._den, self._least, self._at_hold_end,
                  self._probe, self._fresh, self._rev_undo, self._rev_at, self._seated):
            a.fill(0)
        self._seat.fill(-1.0)
        # the last reversal's turn (from the anchor, units), the way into it and the samples
        # since (-1: none pending; PerformanceFrame._reversal_sizes)
        self._rev_turn, self._rev_way, self._rev_age = np.zeros(self.dim), np.zeros(self.dim), -1
        self._size.fill(1.0)
        self._judged.fill(1.0)
        self._best = -1   # none before the first sample: the likeliest then, without the margin
        self._run, self._run_k = 0, -1   # samples in a row best was ok, and whose
        # samples in a row best was blocked, whose, and the best barred (blocked)
        self._blocked, self._blocked_k, self._barred, self._freed = 0, -1, -1, -1
        self._once = np.zeros(len(self.names), dtype=bool)
        self._lost = 0
        # this attempt began at an end read as a return, and whether the pending one is
        # (gesture_end.REANCHOR_RADII)
        self._begun_at_return = self._end_returned = False
        self._shape = np.zeros(len(self.names))
        self._shape_n = 0
        # ... and at each timing offset (commitment.add_lagged)
        self._shape_lag = np.zeros((2 * commitment.COMMIT_LAGS + 1, len(self.names)))
        # the last squared distance off each followed state, and the samples in a row it grew
        # (shape_lead.ShapeLead._drifts)
        self._drift, self._drift_run = np.zeros(len(self.names)), np.zeros(len(self.names))
        self._gone = np.zeros(len(self.names))
        # each template's progress where its current attempt began (validity.stalls)
        self._attempt_from = np.zeros(len(self.names))
        self._acquired = -1
        # begun by abandonment, and the input's way to its anchor (validity.unbegun)
        self._abandoned, self._came = False, np.zeros(self.dim)
        self._abandon_rested = False
        # the input's path since the anchor (still radii), its samples and its last two steps,
        # and whether the attempt was begun under way (under_way.underway), rested since
        self._walk, self._walk_n, self._step_prev, self._step_last = 0.0, 0, 0.0, 0.0
        self._underway, self._underway_rested = False, False
        self._drive_k, self._drive_from, self._drive_peak = -1, 0.0, 0.0
        self._drive_moved = False
        self._drive_leapt = 0.0   # progress leapt while it did not drive (validity.leapt)
        self._turn_in, self._turn_ref, self._turn_h = 0.0, None, None
        self._after_end = 0
        self._peak, self._peak_k = 0.0, -1
        self._end_history: list[float] = []   # handover.tempo_ended
        self._lagged = False   # the end was reached by handover.tempo_ended
        self._end_x: np.ndarray | None = None
        # where the input came nearest the ended template's last point since, and whether it has
        # not yet gone away from it (take_rule.TAKE_FROM_NEAREST)
        self._end_near: np.ndarray | None = None
        self._end_nearing = False
        # the anchor less that point, for the next gesture (None: no end before it)
        self._take_shift: np.ndarray | None = None
        # where a gesture never recognised was followed to its end (gesture_end.UNSEEN_END)
        self._unseen_x: np.ndarray | None = None
        self._unseen_last: np.ndarray | None = None
        self._state: FollowState | None = None
        self._forget_shape()
        self._threshold_ev, self._threshold_x = 0.0, None
        self._taken: list[np.ndarray] = []   # the gesture's last samples (Refusal._fits_take)
        self._stroke_bent = False   # the input left its chord since the attempt began (_strays)

    @property
    def log_constant(self) -> float:
        """The Gaussian's normalising term ``-d log sigma - d/2 log 2 pi`` in every
        log-likelihood."""
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
        """x as contiguous floats of the templates' shape (a row of a column pick is strided,
        which the compiled rules refuse), or None when it holds a non-finite value."""
        x = np.ascontiguousarray(x, dtype=float)
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

    def step(self, x: np.ndarray) -> FollowState:
        """Follow one live sample x (d,) in the templates' units; causal."""
        x = self._sample(x)
        if x is None or self._glitch(x):
            return self._held()
        self._last_x = x.copy()
        fw = self.forward
        step_ll = fw.step(self._inputs(x))
        state = self._finish(step_ll, fw, 0, fw.entries, x)
        fw.seat(self._seat, self._seated)
        return state

    def _glitch(self, x: np.ndarray) -> bool:
        """Whether the finite sample x is a glitch to hold (module docstring); counts it."""
        last = self._last_x
        if last is None:
            return False
        near2 = self._path_distance2(x)
        glitch = not self._jumped and (bool((np.abs(x - last) > self._jump).any())
                                       or (near2 > self._off_limit2 and not self._strayed))
        self._jumped = glitch
        if not glitch:
            self._strayed = near2 > self._on_limit2
        self.glitches += glitch
        return glitch

    def _path_distance2(self, x: np.ndarray) -> float:
        """The finite sample x's squared distance from every likely template's reach
        (:func:`behaviors.mop.glitch.path_distance`); 0 before any template was followed."""
        if self._best < 0:
            return 0.0
        b = self.bank
        return path_distance(np.ascontiguousarray(self._positions(x)), b.means, b.starts,
                             b.lengths, self.forward.mean, self._evidence, self._refused, 0,
                             len(self.names), self.dim, REACH_BACK, REACH_AHEAD)

    def same_parameters(self, other: "ActionFollower") -> bool:
        """True when ``other`` follows with the same parameters (its templates may differ)."""
        return self._params == other._params

