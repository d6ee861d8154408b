"""The threshold model's evidence beside the templates' and its lead (gesture spotting): each
sample steps the threshold model (:mod:`behaviors.mop.threshold`: every template's states
ergodic, and its mirror chains) as the templates see it, its evidence forgotten as theirs; a new
attempt starts with the lead it held over the best template
(:meth:`ThresholdLead._threshold_lead`; figures in :mod:`behaviors.mop.threshold`).

Mixin of :class:`~behaviors.mop.follower.ActionFollower` under
:class:`~behaviors.mop.refusal.Refusal`; the group's form is :mod:`behaviors.mop.threshold_kernel`.
Evidence in nats; samples in the input's units.
"""

from __future__ import annotations

import numpy as np

from behaviors.mop import threshold


class ThresholdLead:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: the threshold model's evidence
    and its lead over the templates."""

    def _setup_threshold(self) -> None:
        """The threshold model's constants and state (after the bank is built)."""
        b = self.bank
        # the ergodic states' weights, then the mirror chains' (threshold.threshold_model_step)
        self._threshold_alpha = np.zeros(2 * len(b.means), dtype=threshold.PRECISION)
        self._threshold_scratch = np.zeros(2 * len(b.means), dtype=threshold.PRECISION)
        self._threshold_means = np.ascontiguousarray(b.means, dtype=threshold.PRECISION)
        self._threshold_lengths = np.ascontiguousarray(b.lengths, dtype=np.int64)
        self._threshold_const = -b.dim * np.log(self.sigma) - 0.5 * b.dim * np.log(2.0 * np.pi)

    def _threshold_evidence(self, x: np.ndarray, anchor: np.ndarray, lead_ll: float) -> float:
        """Step the threshold model (:mod:`behaviors.mop.threshold`) with sample ``x`` seen from
        ``anchor`` and return its evidence, forgotten as the templates' (``lead_ll``: this
        sample's raw log-likelihood under the template of most evidence). Started afresh with
        the evidence."""
        b = self.bank
        if self.invariance == "none":
            z = (x - b.center) / b.scale
            jac = -self._jacobian
        else:
            z = (x - anchor)[None, :] / b.scale
            jac = -self._jacobian
            if self.invariance == "scale":
                z /= self._size[:, None]
                jac = jac - self.dim * np.log(self._size)
            z += self._first_z
        step = threshold.threshold_model_step(
            threshold.mirrored_column(z, self._first_z), self._threshold_means,
            self._threshold_lengths, self.sigma, self._threshold_const,
            np.ascontiguousarray(jac, dtype=float), self._threshold_alpha,
            self._threshold_scratch, self._threshold_x is None, threshold.STAY)
        step = threshold.gated(step - self.threshold, lead_ll, x, self._threshold_x,
                               self._still_radius)
        self._threshold_x = x
        self._threshold_ev = self._threshold_ev * self._decay + step
        return self._threshold_ev

    def _threshold_lead(self) -> float:
        """How far the threshold model's evidence leads the best template's, or 0 when it does
        not, its mirror chains hold under :data:`~behaviors.mop.threshold.CARRY_CHAINED` of its
        weight or it has not been stepped since the attempt began: what it starts a new attempt
        with (see :mod:`behaviors.mop.threshold`)."""
        n = len(self.bank.means)
        if (self._threshold_x is None or not threshold.CARRY_LEAD
                or float(self._threshold_alpha[n:].sum()) < threshold.CARRY_CHAINED):
            return 0.0
        return max(0.0, self._threshold_ev - float(np.max(self._evidence)))
