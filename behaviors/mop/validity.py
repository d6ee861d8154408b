"""When a followed template may drive its character: refusal (and what was tried beside it).

Refusal (null rejection), per template against its own spread (:mod:`behaviors.mop.hmm`):
per-step log-likelihoods forgotten with ``null_memory`` samples, read as an RMS distance in
``sigma`` units. Beyond ``null_distance`` the template is refused; it is accepted again below
``accept_distance`` (hysteresis, not a permanent latch: with the bird alone in
``tests/mop/test_live.py`` the latch and the hysteresis took the same 3 of 17 other gestures
at 60% with one spread per template, and the hysteresis takes 0 with one per column).
Tighter limits did not separate unrelated motion from true performances: null 1.4 / accept
1.05 cut true validity after 30% from 0.90 to 0.75 while unrelated motion stayed 0.55-0.62
valid; 1.1 / 0.85: 0.65 and 0.51.

Tried beside the likelihood, measured with ``bench/follow_quality.py`` and left out, since the
unrelated motions still find stretches of some template that match them in every respect
these rules see (a diagonal line is the chord of a circle's first quarter at 1.5x; a stroke of
a triangle is the outward half of the line):

- Direction of motion at the followed state (``1 - |cos|`` of the angle between the input's
  velocity and the template's, going back allowed, averaged over the recent moving samples):
  over 2 samples with the input moving above a quarter of the template's median speed it cut
  the worst unrelated share from 0.76 to 0.58, but valid after 30% of gestures at 0.7-1.4x fell
  from 0.92 to 0.89 and a puck's jitter during a vertical lift's hold read as crossing motion
  (hold RMSE max 0.06 -> 0.44); over 4 samples with the input above 3x that speed it changed
  nothing measurable (unrelated 0.664 with and without), above 1.5x it made it 0.69.
- Pace: the template path covered by the followed progress against the input's displacement
  over 8 samples (true performances 0.61-1.36 in 96% of samples, unrelated ones below 0.38 in
  10%): unrelated 0.664 -> 0.637 while valid after 30% fell to 0.895; stricter, 0.59 but
  0.85 and holds lost.
- Distance at the followed state instead of the predictive likelihood (which carries the
  transitions' uncertainty, about 1 sigma even on exact copies): exact copies 0.64 sigma
  (median), unrelated motions while valid 0.87: no threshold separates them, since a state is
  0.7 sigma from the next on a 61-sample circle at sigma 0.2.
- Rivals: letting a template drive only while no other engaged, unrefused template explained
  the recent samples about as well (within 0.5 sigma) stopped the line from driving the start
  of a square, but with twenty templates some other template nearly always fits as well: valid
  after 30% of gestures at 0.7-1.4x fell from 0.92 to 0.59 (margin 0.1: 0.73). Checked only
  before a template is recognised (once valid it stays so): 0.91 -> 0.82 at margin 0.3 (0.72
  at 0.6), while the longest wrong-valid run back to back fell from 11 to 5 samples (median);
  recognition at 30% of gestures 0.73 -> 0.47.
"""

from __future__ import annotations

import numpy as np


class Validity:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: refusal."""

    def _refuse(self, dist2: np.ndarray) -> None:
        """Refusal with hysteresis from the recent squared distances (sigma units), in place on
        ``_refused``."""
        self._refused |= dist2 > self._null2
        self._refused &= ~(dist2 < self._accept2)
