"""BestMatch in the Python step (:class:`step.GenerationStep` inherits it; the compiled step,
step_kernel, repeats it): the balanced choice between the situation and the coherence windows
(paper section 4.3.3), with a demonstrated charge or dart the match has entered kept whole.
Units: seconds, table metres.
"""

from __future__ import annotations

import math

from behaviors.puppet_master.darts import dart_goes_on
from behaviors.puppet_master.step_detail import StepDetail


class StepMatch(StepDetail):
    """BestMatch of :class:`engine.Reactor` (its state: see Reactor.start)."""

    def _best_match(self, mx: float, my: float) -> int:
        """BestMatch (section 4.3): the training index to generate from (the sample after
        the best window; sets ``source``, ``last_choice`` and the charge kept whole)."""
        b = self.behavior
        # BestMatch over the windows ending at the previous step
        js, cost_s = self.situation.best()
        jc, cost_c = self.coherence.best()
        use_c = self.balancer.choose(cost_s, cost_c)
        target = (jc if use_c else js) + 1
        self.last_choice = "coherence" if use_c else "situation"
        # a charge the match has entered is kept whole to the end of its push
        # (demonstrated.charges): the bully's matches joined charges partway and left them within
        # a few steps (14 jumps in 26 steps), so it went 9-14 cm short of its main while the
        # matched moments touched (contact 0.02-0.08 against 0.157 on all nine unseen paths);
        # entered in its run-up only (demonstrated.charge_entries: joined in its push, a push
        # followed another back to back)
        self._charge_ended = False
        rx, ry, _ = self.pose
        mxp, myp = self.main_motion.x, self.main_motion.y
        if 0 <= self.source < self._dart_end and math.hypot(
                rx - mxp, ry - myp) > b.distance[self.source] and dart_goes_on(
                self._main_recent, b.dart_span, b.span_approach[self.source + 1], self.dt, mx,
                my, rx - mxp, ry - myp):
            # a dart the match has entered is kept whole to its bottom while the friend is
            # farther out than its moment (darts.py: why; the figures at _trajectory's dart)
            self.source = target = self.source + 1
            self.last_choice = "dart"
            return target
        self._dart_end = b.dart_end[target]
        if 0 <= self.source < self._charge_end:
            target = self.source + 1
            self.last_choice = "charge"
        else:
            self._charge_ended = self._charge_end >= 0   # its push has ended (see _detail)
            self._charge_end = b.charge_end[target]
            if self._charge_end >= 0:
                # with the texture of the charge itself: a patch begun at a slower moment
                # turned its steps by 0.7-0.9 rad RMS (0.5 in the demonstration's fast
                # moments). Measured: 307 -> 308 of 360 on seeds 0-2, seed 7 103 -> 104
                self.patch.restart()
        self.source = target
        return target
