"""Recognition, one sample at a time: evidence, probabilities, best and validity (MOP section
3.2 with several templates).

Mixin of :class:`~behaviors.mop.follower.ActionFollower` (which builds the follower, its
parameters and state): once the forward step gave every template's log-likelihood of the
sample, :meth:`Recognition._finish` updates the per-template evidence, sizes, refusal and
engagement, and :meth:`Recognition._conclude` chooses ``best``, decides whether it drives
(``valid``) and builds the :class:`~behaviors.mop.state.FollowState`, then spots where the
gesture ends (:mod:`behaviors.mop.spotting`). A group steps its members through
``_conclude`` after updating their arrays at once (:mod:`behaviors.mop.group`). Figures come
from ``bench/follow_quality.py`` unless said otherwise.

- Probabilities: each template's evidence is its sum of per-step log-likelihoods of the *raw*
  sample (its own scale and the estimated size enter as the Gaussian's Jacobian, so templates of
  different sizes compare fairly), forgotten with time constant ``memory`` samples; a softmax
  gives probabilities summing to 1. ``best`` changes only when another template leads by
  ``switch_margin`` nats, and drives only while at least ``min_probability`` likely. The
  Jacobian favours narrow templates wherever templates fit alike (the jump ankle's -7.29 against
  the circle's -5.99: 1.3 nats a sample), and among twenty templates back to back the narrowest
  hold ``best`` while a broader true one is late (the held-out jump ankle 179 ticks of them, the
  tuned spin ankle 93). Measured and not kept: each Jacobian taken halfway to the set's mean in
  the evidence and the threshold model (not in :mod:`behaviors.mop.rivals`'s breadth).
  ``bench/follow_seeds.py --sections=sequences``: twenty longest wrong run 4/5/7/2/2/4 ->
  4/4/7/2/2/4 (101-106), 3/6/4/4/5/4 -> 3/6/4/3/4/2 (107-112), within 20% 103 0.219 -> 0.281, 104
  0.313 -> 0.344, 110 0.406 -> 0.438, the rest unchanged; ``bench/follow_quality.py`` (tuned /
  held-out) within 20% unchanged, tuned twenty recognition median 0.298 -> 0.267, valid after 30%
  at 0.7-1.4x 0.9117 / 0.9022 -> 0.9187 / 0.9040, but unrelated mean 0.0109 / 0.0128 -> 0.0130 /
  0.0140 (worst 0.058 -> 0.063), pauses valid after 0.941 -> 0.930, bent 5% 0.8646 -> 0.8465,
  held-out aspect 1.2 0.427 -> 0.394; held-out seeds 101-106 sized mean 0.8884 -> 0.8905 but 105
  0.8860 -> 0.8812, unrelated worst 104 0.111 -> 0.116. Taken all the way to the mean: 102 and
  103's runs (spin wrist / circle, punch ankle / getup wrist) 5 / 7 -> 2 / 2, but 105 2 -> 3 and
  106 4 -> 6. A quarter of the way: runs 4/4/7/2/2/4 and 3/6/4/2/5/2, within 20% 110 only, but an
  unrelated stroke after a gesture (unambiguous) 0.072 -> 0.116, held-out valid after 30% 0.9022
  -> 0.9016 (105 0.8860 -> 0.8793), bent 10% 0.621 -> 0.609, held-out aspect 1.2 0.427 -> 0.401.
  Nor only among templates that fit alike (each Jacobian toward the weighted mean of those whose
  evidence without it lies within 6 nats of the best, weight falling to 0 there): held-out 108's
  circle at 1.2x and the spin wrist fit within 0-2 nats (the circle better) and the spin leads by
  8-10 nats of density alone; evened, neither drives (twenty avoidable wrong runs 107-112 worst
  3 -> 2, 101-106 mean 1.5 -> 1.0), but sized valid after 30% lower on every seed 107-112 (mean
  0.9109 -> 0.9017, 112 0.9123 -> 0.8889) and within 20% or by the reach + 0.05 mean 0.521 ->
  0.490: the broad template's own-unit fit is the better one wherever the raw input is alike
  (110's true spin wrist: the circle fits 1.2-2.5 nats better; evened to 8 nats it drives 4).
- Engagement: a template drives nothing until its progress passed its onset (the first state
  ``onset`` sigmas from its first state) *and* the input itself left the anchor by as much: a still
  input lets the transitions' prior drift along the first states (a still tail after a diagonal
  line re-engaged the circle within 6 samples). Valid = ``best`` engaged, not refused, its followed
  progress past ``coverage`` of its path (or less, :mod:`behaviors.mop.coverage`) and the input on
  its path (``shape_*``, :mod:`behaviors.mop.refusal`), its spread at most ``max_spread`` (in
  states), its end not yet reached, for ``confirm`` samples in a row (or one that alone widened
  its shape lead by :data:`~behaviors.mop.shape_lead.CONFIRM_GAIN`). An action not yet driving
  must also lead every other likely template in shape since the gesture began, and one that reached
  its end drives at most two samples more (:mod:`behaviors.mop.spotting`).
- Its own confirmation: the ``confirm`` samples are the action's own (``_run_k``: whose run it
  is); a new ``best`` starts its run afresh. Carried over, a crawl's run let the figure eight
  drive in the very sample it took over (the crawl at 0.81x, its follower stalled at 0.20 with
  its size still 1.02, refused at 0.31). Twenty templates back to back, tuned joints, seeds 1-6
  (``bench.motions.back_to_back`` x8 each, not the bench's draws): that run 9 -> 8 ticks,
  every other sequence the same; ``bench/follow_quality.py --sections=sequences`` the same but
  for held-out twenty templates (longest wrong run median 3 -> 2.5, max 11 both);
  ``--sections=unrelated,after,sized`` (tuned / held-out): valid after 30% at 0.7-1.4x 0.9131 /
  0.9038 -> 0.9129 / 0.9033 (a true take after another action led waits a sample), unrelated
  mean 0.0481 / 0.0556 -> 0.0478 / 0.0550, after a gesture 0.1146 / 0.1159 -> 0.1145 / 0.1147.
  Measured and not kept: a take held until the action has been ``best`` for ``h`` times its
  template's length in samples in a row (a hysteresis scaled by each template's own rate; every
  take). Every take among the held-out twenty back to back (``bench/follow_seeds.py
  --sections=sequences``, seeds 101-112; 108 right takes within 20%, 25 wrong ones inside a
  gesture): the wrong ones had been best 4-13 samples when they drove (the spin wrist on a
  circle 5-13, the punch ankle on a getup wrist 6-7, the line on a square 4-13), 82 of the 108
  right ones 2-5; a hysteresis holds more right takes than wrong ones at every ``h`` (0.03: 13
  right, 0 wrong; 0.05: 19, 2; 0.07: 42, 4; 0.1: 67, 11). At 0.1: twenty within 20% 0.344 /
  0.281 / 0.219 / 0.313 / 0.156 / 0.25 -> 0.156 / 0.156 / 0.156 / 0.188 / 0.156 / 0.25 (101-106),
  0.281 / 0.25 / 0.188 / 0.406 / 0.313 / 0.344 -> 0.219 / 0.125 / 0.094 / 0.25 / 0.281 / 0.281
  (107-112), six 0.031-0.188 -> 0 on every seed; longest wrong runs 4/5/7/2/2/4 -> 4/2/6/2/2/3
  and 3/6/4/4/5/4 -> 3/6/4/4/2/4. Nor is the true action's evidence rising on the one taken when
  a wrong take drives: its gain over the last 3 samples -4.0 to +2.3 nats at 23 of those 25.
- Mirrored paths among twenty templates (``bench/follow_widened.py``: worst valid share 0.239,
  mean 0.0145, 22 of 540 over 0.1) drive where a stroke is followed back over itself (the
  zigzag taken at its corner and followed back along the stroke; the walk ankle on the
  mirrored spin ankle), at sizes near the top of ``scale_range``, or as forward fits no rule
  tells from true ones. Stopping an action followed back 15% of its extent unless it carried
  the performer 0.2 forward, plus no drive at 0.97 of the top size: worst 0.184, but a
  performer's genuine rewind stopped (a circle taken back from 0.35 to 0.1 drove 3 of its 14
  samples, 14 without the rule) and sizes near the top were lost (1.75x valid after 30% 0.567
  against 0.742); sparing slides above where the drive began: worst 0.222, the rewind 7 of 14.
  Not kept: a rewind is the paper's own (the forward window follows a performer back).
- Small gestures back to back (0.6-0.8x, six templates): 9.4% of seed 29's never drive, most
  of them lines: along a straight stroke size and progress look alike, so a 0.7x line is
  followed as a full one, reaches its turn at about 0.37 of the template, and its return is
  read as the stroke going backwards. Following a template sized at a turning point up to 9
  states ahead from that turning point (only while its followed state went forward) made it
  0, and sized 0.7-1.4x valid after 30% 0.9157 -> 0.9231; but on the held-out performers
  unrelated motions drove more (worst 0.346 -> 0.450) and sized ones less (0.9049 -> 0.9026):
  not kept.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.mop import bends
from behaviors.mop.blocked import (BLOCKED_SAMPLES, BLOCKED_SIZE, blocked_run, lead_of_size,
                                   likeliest_other)
from behaviors.mop.forward import WindowedForward
from behaviors.mop.fresh_refusal import refuse
from behaviors.mop.gesture_end import drives
from behaviors.mop.handover import finished
from behaviors.mop.holding import SNAP_RADII, rested_sizes, shown_progress
from behaviors.mop.state import ByName, FollowState
from behaviors.mop.tempo import crawl_run, crawls, resting
from behaviors.mop.validity import (CARRY_FIRST, PAUSE_CARRY, PAUSE_SAMPLES, backs_first,
                                    carried, leapt, rests_behind, stalls, still_unbegun,
                                    unbegun, unjudged, unweighed)


class Recognition:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: one sample's evidence,
    probabilities, best, validity and state."""

    def _finish(self, step_ll: np.ndarray, forward: WindowedForward, offset: int,
                entries: np.ndarray, x: np.ndarray) -> FollowState:
        """Evidence, probabilities, best, validity and spotting from one forward step's
        per-template log-likelihoods; this follower's templates are ``forward``'s from
        ``offset`` on."""
        k = len(self.names)
        b = self.bank
        # every sample joins the take's last samples, a rest's too (take_rule._remember_take)
        self._remember_take(x)
        mean = forward.mean[offset:offset + k]
        g = b.starts + np.minimum(mean, b.lengths - 1.0)
        gi = np.minimum(g.astype(np.intp), b.starts + b.lengths - 2)
        frac = g - gi
        src = b.source
        progress = src[gi] + frac * (src[gi + 1] - src[gi])
        # resting over this sample and the ones before (the samples _still will keep): once,
        # for the holds here and for the stall rule after the push (_conclude)
        rest = resting(self._recent_x[1 - self.still_samples:] + [x], self._still_radius)
        if self._holds is not None:   # holds inside a template (behaviors.mop.holding)
            if rest and self.invariance == "scale":
                rested_sizes(self._holds[1][gi], self._rel, (x - self._anchor) / self._units,
                             self._size,
                             self.scale_range[0], SNAP_RADII * self._still_radius / self._units,
                             self._num, self._den, self._prior, self._least, self.bank.starts,
                             self._seat)
        self._reversal_sizes(x, gi)
        self._estimate_size(x, gi, frac)
        if self._holds is not None:
            progress = shown_progress(progress, self._holds[0][gi], self._at_hold_end, rest,
                                      self._holds[2][gi])
        raw_ll = step_ll - self._jacobian
        if self.invariance == "scale":
            # (measured and not kept, no size Jacobian while resting: held-out seed 108 sized
            # valid after 30% 0.8906 -> 0.8904, a 0.7x walk wrist paused 0.568 -> 0.523)
            raw_ll = raw_ll - self.dim * np.log(self._size)
        # none in a pause of an action that carried its performer forward (validity.unweighed;
        # measured and not kept, nor of one taken validity.TAKEN_PERFORMED past where its attempt
        # began: held-out seeds 108 / 102 sized identical, 0.8906 / 0.8976). The pause is read
        # over validity.PAUSE_SAMPLES too where the action carried its performer PAUSE_CARRY on
        # (the figures there). Screened beside no reversal read at rest (reversal.py), the
        # evidence put back at a rest's onset as it was 3 samples before, where the action
        # driving then had carried its performer: held-out 102 sized .9053 -> .9100, the 1.4x
        # wave .455 -> .924 as with the 4 samples; 5 samples back, 108's 0.7x walk wrist .568 ->
        # .545
        carried_on = carried(self._acquired, self._drive_from, self._drive_peak,
                             self._drive_moved)
        paused = rest or (carried_on and self._drive_peak - self._drive_from >= PAUSE_CARRY
                          and resting(self._recent_x[1 - PAUSE_SAMPLES:] + [x],
                                      self._still_radius))
        weighed = not unweighed(paused, carried_on)
        if weighed:
            self._evidence *= self._decay
            self._evidence += raw_ll
        # none while the performer rests (validity.unjudged), but on a fresh start
        upd = self._recent_weight <= 0 if unjudged(rest) else slice(None)
        self._recent[upd] = self._recent[upd] * self._null_decay + step_ll[upd]
        self._recent_weight[upd] = self._recent_weight[upd] * self._null_decay + 1.0
        new = entries > self._entries   # re-entered: a new performance, judged afresh
        self._entries[:] = entries
        # a refused template whose performance is back at its start, matching it, may begin
        # anew (re-entry is not counted while the main window already holds the first states)
        back = self._refused & (mean < self._onset_state)
        if np.count_nonzero(back):
            back &= (self._log_constant - step_ll) * (2.0 / self._zdim) <= self._null2
            new |= back
        self._rejudge()
        if np.count_nonzero(new):
            self._gone[new] = 0.0
            self._attempt_from[new] = progress[new]
            self._seated[new] = False
            self._recent[new] = self._log_constant
            self._recent_weight[new] = 1.0
            self._refused[new] = False
            self._engaged[new] = False
            self._fresh[new] = False
        mean_ll = self._recent / self._recent_weight
        dist2 = (self._log_constant - mean_ll) * (2.0 / self._zdim)
        # (a template just judged afresh waits a few samples: fresh_refusal)
        refuse(self._refused, self._fresh, dist2, self._recent_weight, self._null2, self._accept2)
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
        total = p.sum()
        p /= total
        # the threshold model competes as one more, never driving, explanation: the share of
        # the probability the templates keep against it (the states' probabilities are the
        # templates' among themselves)
        self._kept = 1.0
        if math.isfinite(self.threshold):
            # (not stepped either in such a pause: validity.unweighed)
            rival = (self._threshold_evidence(x, self._anchor, float(raw_ll[top])) if weighed
                     else self._threshold_ev) - self._evidence[top]
            self._kept = total / (total + math.exp(min(rival, 700.0)))
        lists = (progress.tolist(), p.tolist(), mean_ll.tolist())
        return self._conclude(top, p, progress, g, gi, mean_ll, new, step_ll, forward, offset, x,
                              lists, rest)

    def _conclude(self, top: int, p: np.ndarray, progress: np.ndarray, g: np.ndarray,
                  gi: np.ndarray, mean_ll: np.ndarray, new: np.ndarray, step_ll: np.ndarray,
                  forward: WindowedForward, offset: int, x: np.ndarray,
                  lists: tuple[list, list, list], rests: bool) -> FollowState:
        """The rest of :meth:`_finish` once the per-template arrays are updated (a group updates
        them for all its followers at once): best, validity, the state and spotting. ``top``:
        the template of most evidence; ``p``: probabilities; ``lists``: progress, ``p`` and
        ``mean_ll`` as lists (for the state's dictionaries); ``rests``: the performer
        rests (:func:`~behaviors.mop.tempo.resting` over the samples ``_still`` keeps)."""
        b = self.bank
        src = b.source
        # best is chosen on the evidence, the narrow templates' Jacobian included. Measured and
        # not kept: best chosen (and switched, on the margin) on the evidence plus a * jacobian *
        # its decayed sample weight, the evidence, probabilities and validity left as they are.
        # follow_seeds.py (101-112) twenty longest wrong run 4/5/7/2/2/4 3/6/4/4/5/4 -> (a=1)
        # 4/3/6/2/2/3 3/5/4/2/2/2, within 20% 104 0.3125 -> 0.3438; but sized valid after 30%
        # worse on every seed (mean 0.8815 -> 0.8703; follow_quality held-out 0.9022 -> 0.8946,
        # under its 0.9), bent 5% 0.8646 -> 0.8374, held-out aspect 1.1 0.8674 -> 0.8320: the
        # Jacobian also makes a true narrow gesture best early. a=0.5: runs 4/4/7/2/2/4
        # 3/6/4/3/5/3, within 20% 104 -> 0.3438, 110 0.4062 -> 0.4375; sized mean 0.8809 (worst
        # 0.8653 -> 0.8626), unrelated mean 0.0109 -> 0.0122, bent 5% -> 0.8438. Switching only
        # when the new top leads on both (a=1): no sequences figure moved. a=1 once a gesture ended
        # (after _restart_here): runs 4/3/7/2/2/3 3/6/4/2/2/2, within 20% unchanged, sized
        # 101-106 still lower on every seed (0.9022 -> 0.8984 on 101), unrelated 104 0.1112 ->
        # 0.1135.
        # (each template's path misfit first: the barred best's release reads it)
        self._judge_shape(x, g, new, rests)
        # a small best kept from driving BLOCKED_SAMPLES in a row is barred while it leads
        # and a rival trails it by no more than its size earns it (blocked.lead_of_size);
        # freed once it no longer leads, began anew, or may drive (_gone: as _shares reads it
        # below; the figures: blocked)
        barred = self._barred
        if barred >= 0:
            np.maximum(self._gone, progress, out=self._gone)
            if barred != top or new[barred] or not (
                    self._shares(barred, float(g[barred]), progress)
                    or self._slow_take(barred, g, x, self._shape_n + 1)[0]):
                self._freed, barred = barred, -1   # (barred at once if blocked again)
                self._barred = -1
        if barred >= 0:
            top = likeliest_other(self._evidence, 0, len(self.names), barred)
        if (self._best < 0 or self._evidence[top] - self._evidence[self._best] > self.switch_margin
                or self._refused[self._best] or self._best == barred):
            self._best = top
        committed = -1   # committed to by shape: best, however improbable (spotting)
        if self.invariance != "none":
            self._add_shape(x, gi, g - gi, rests)
            committed = self._committed()
            if committed >= 0:
                self._best = committed
        bi = self._best
        progress_list, p_list, mean_ll_list = lists
        engaged = bool(self._engaged.any())
        slope = src[gi[bi] + 1] - src[gi[bi]]
        var = forward.var_of(offset + bi)
        variance = var * slope * slope
        # the spread limit counts states, not the progress a compressed hold spans
        spread2 = var / (b.lengths[bi] - 1.0) ** 2
        still = self._still(x)
        # the probabilities the validity reads: among the templates but a barred best (blocked;
        # ``top``: the likeliest of them)
        pv, kept = p, self._kept
        if barred >= 0 and barred != bi:
            pv = np.exp(self._evidence - self._evidence[top])
            pv[barred] = 0.0
            others = pv.sum()
            pv /= others
            if math.isfinite(self.threshold):
                rival = self._threshold_ev - self._evidence[top]
                kept = others / (others + math.exp(min(rival, 700.0)))
        ok = bool(self._engaged[bi] and not self._refused[bi] and self._shaped(bi)
                  and spread2 <= self.max_spread ** 2
                  and (pv[bi] * kept >= self.min_probability or committed == bi)
                  and (self._end_x is None or not self._moved_on(x, bi)))
        overran = False
        if self.invariance != "none":
            # each template's highest progress (spotting._shares, shape_lead._broad_rivals)
            np.maximum(self._gone, progress, out=self._gone)
            # a new action drives only once its shape clearly leads (shape_lead.LEAD)
            leads = self._leads(bi, pv * kept, progress)
            # ... and once the input turned as the template does (turning.turning)
            turned = self._turned(x, bi, float(g[bi]))
            # ... and once it is not taken at a crawl (tempo.slow_take); nor does any action
            # drive once it crawled so for CRAWL_SAMPLES samples in a row (tempo.crawls)
            slow, hovers = self._slow_take(bi, g, x)
            # ... and it is not shown valid while the input overruns its path (overrun.overruns;
            # the rules go on as if it were)
            overran = self._overruns(bi, g, x, progress_list[bi])
            # ... nor just before a straight first stroke's bend while the input goes on
            # straight (bends.unturned)
            overran = overran or bends.unturned(float(self._before_bend[int(g[bi])]),
                                                self._turn_in)
            # ... nor while the input draws a straight stroke its path so far strays from
            # (bends.strays)
            overran = self._strays(bi, int(g[bi]), x) or overran
            self._crawl = crawl_run(self._crawl, bi == self._crawl_k, slow,
                                    hovers and self._drive_k != bi)
            self._crawl_k = bi
            # ... nor while the input goes back the way it came to an abandonment's anchor
            # (validity.unbegun), nor in an attempt abandoned under way (under_way.underway),
            # until the performer moves on after a rest
            back = unbegun(self._abandoned, x - self._anchor, self._came) or self._underway
            self._underway, self._underway_rested = still_unbegun(self._underway,
                                                                  self._underway_rested, rests)
            self._abandoned, self._abandon_rested = still_unbegun(self._abandoned,
                                                                  self._abandon_rested, rests)
            shares = self._shares(bi, float(g[bi]), progress)
            # ... nor one barred since it began (blocked)
            self._once[new] = False
            ok = ok and not self._once[bi] and not crawls(self._crawl)
            # (measured and not kept, no new take while the performer rests: a stroke ended
            # where the held-out walk wrist turns back took it 7-20 samples into the rest, own
            # strokes told 104 0.219 -> 0.144, 110 0.190 -> 0.149; but sized valid after 30% on
            # 104 0.9099 -> 0.9066: true getup and walk wrists are taken in their own waits)
            # ... nor while the performer rests on a straight stroke where its template has
            # turned (bends.bent_rest)
            bent = self._turn is not None and bends.bent_rest(
                rests, float(self._turn[int(g[bi])]), self._turn_in)
            ok = ok and not self._drifts(bi) and (
                self._acquired == bi or (leads and turned and not slow and not back
                                         and not shares and not bent))
            # (blocked: taken at a crawl at a small size, not driving)
            blocked = (self._acquired != bi and bool(self._engaged[bi])
                       and self._size[bi] < BLOCKED_SIZE and self._crawl > 0)
            self._blocked = blocked_run(self._blocked, bi == self._blocked_k, blocked)
            self._blocked_k = bi
            # ... while a rival may trail it by no more than its small size earns it
            if len(self.names) > 1 and (0 < BLOCKED_SAMPLES <= self._blocked
                                        or blocked and bi == self._freed) and lead_of_size(
                    self._evidence, 0, len(self.names), bi, float(self._size[bi]),
                    float(self.dim), self.memory):
                self._barred = bi
                self._once[bi] = True
            self._remember_tempo(g - b.starts, x)
            if self._drive_k == bi:
                # (its followed state's last step: the action's progress at the last sample)
                last = (self._end_history[-1] if self._peak_k == bi and self._end_history
                        else progress_list[bi])
                step = (progress_list[bi] - last) * (b.lengths[bi] - 1.0)
                # a leap taken while it did not drive carries no one (validity.leapt)
                self._drive_leapt += leapt(self._acquired == bi, step) / (b.lengths[bi] - 1.0)
                # an action that has not yet carried its performer forward does not drive
                # them back behind where it began (validity.backs_first)
                self._drive_peak = max(self._drive_peak, progress_list[bi])
                ok = ok and not backs_first(self._drive_from, self._drive_peak, progress_list[bi])
                # ... nor once its performer finished it short of its end (handover.finished)
                ok = ok and not finished(self._drive_peak, progress_list[bi], self._crawl > 0)
                # ... nor, once the performer moved it without carrying it forward, hold them
                # while they stop (validity.stalls)
                # (none on a hold it was seated on: holding.rested_sizes)
                ok = ok and (self._seated[bi] or not stalls(
                    self._drive_from + self._drive_leapt, self._drive_peak, self._drive_moved,
                    rests, self._drive_from - self._attempt_from[bi], abs(step)))
                # ... nor hold them resting behind where it began (validity.rests_behind)
                ok = ok and not rests_behind(self._drive_from, progress_list[bi], rests)
                # ... and it is not shown while its performer halts, not yet carried forward,
                # where its template goes on (halts.halts)
                overran = overran or (
                    self._drive_peak - self._drive_from < CARRY_FIRST
                    and self._halts(bi, float(g[bi] - b.starts[bi]), progress_list[bi], x))
        # a new best confirms on samples of its own: the run of the one before does not carry
        # over (it did: a figure eight took over a stalled crawl and drove in the same sample)
        self._run = self._run + 1 if ok and bi == self._run_k else int(ok)
        self._run_k = bi
        # an action that reached its end drives at most END_GRACE samples more (spotting)
        self._after_end = self._after_end + 1 if self._end_x is not None else 0
        # Measured and not kept: no confirmation for the action committed to by shape (its fit
        # and lead are its own confirmation; 2-5 of 32 back-to-back gestures a set wait for it
        # alone past the reach + 0.05). bench/follow_quality.py: six held-out within 20% or by
        # the reach 0.469 -> 0.50, twenty tuned 0.50 -> 0.531, no wrong run longer; but every
        # unrelated take committed to drives a sample sooner: unrelated mean 0.0100 -> 0.0107
        # (the diagonal among six 0.013 -> 0.035), after a gesture mean 0.045 -> 0.046.
        # (or on its first: shape_lead.CONFIRM_GAIN)
        run = self.confirm if self._confirms_itself(bi) else self._run
        valid = drives(run, self.confirm, self._after_end)
        if valid and self._drive_k != bi:
            self._drive_k = bi
            self._drive_from = self._drive_peak = progress_list[bi]
            self._drive_leapt = 0.0
            self._drive_moved = False
        if valid and not rests:
            self._drive_moved = True
        self._acquired = bi if valid else -1
        loglik = mean_ll_list[bi]
        names = self.names
        likely: tuple[tuple[str, float, float], ...] = ()
        if not still and (engaged or self._displacement(x).max() >= self.hint_onset * self.sigma):
            order = [i for i in np.argsort(-p, kind="stable")[:3] if not self._refused[i]]
            likely = tuple((names[i], p_list[i], progress_list[i]) for i in order)
        shown = progress_list
        best, best_progress = names[bi], progress_list[bi]
        if self._ended >= 0 and not engaged:
            # the last gesture ended and no new one has begun: it stays at its end, not driving
            best, best_progress = names[self._ended], 1.0
            shown = list(progress_list)
            shown[self._ended] = 1.0
        index = self._index
        state = self._state = FollowState(
            best=best, progress=best_progress, variance=variance,
            probabilities=ByName(index, p_list), progress_by=ByName(index, shown),
            valid=valid and not overran, loglik=loglik, distance=self.distance_of(loglik),
            restarted=bool(new[bi]),
            loglik_by=ByName(index, mean_ll_list), likely=likely,
            # the sizes after this sample (a refused take may have resized its template here,
            # take_rule.TAKE_RESIZE), as the group reports them
            scale_by=ByName(index, self._size.tolist()),
            holding=bool(b.holds[int(round(g[bi]))] or progress_list[bi] >= 0.9))
        if engaged:
            self._ended = -1
        if self.invariance != "none":
            self._spot(valid, ok, engaged, still, bi, progress_list[bi], step_ll[bi], x, forward,
                       offset, rests)
        self._state = state
        return state
