"""When a followed template may drive its character: refusal and shape consistency.

Refusal (null rejection), per template against its own spread (:mod:`behaviors.mop.hmm`):
per-step log-likelihoods forgotten with ``null_memory`` samples, read as an RMS distance in
``sigma`` units. Beyond ``null_distance`` the template is refused; it is accepted again below
``accept_distance`` (hysteresis, not a permanent latch: with the bird alone in
``tests/mop/test_live.py`` the latch and the hysteresis took the same 3 of 17 other gestures
at 60% with one spread per template, and the hysteresis takes 0 with one per column).
Tighter limits did not separate unrelated motion from true performances: null 1.4 / accept
1.05 cut true validity after 30% from 0.90 to 0.75 while unrelated motion stayed 0.55-0.62
valid; 1.1 / 0.85: 0.65 and 0.51.

Shape consistency along the path.
The forward algorithm aligns a performance to the template state that best explains the
*position* of each sample; a path that is none of the actions still finds, for a while, states
close enough to it (a diagonal line lies within tolerance of the chord of a circle's first
quarter at 1.5x its size, and the progress then stalls while the performer goes on). What such
paths do not share with the template is the direction of motion at the followed state: the
performance moves across the template's path instead of along it. Direction is blind to tempo
and size (the size estimate and the time warp cannot absorb it), so it is judged on its own,
beside the likelihood, as a *misfit* per template: ``1 - |cos|`` of the angle between the input's
velocity and the template's direction at the followed state (0 along the path, forward or
back: a performer may go back along it; 0.29 at 45 degrees; 1 across it), counted only while
both move, averaged over ``direction_memory`` samples of motion; beyond ``direction_limit``
the template is refused, below ``direction_accept`` (and the distance below its own acceptance)
it is accepted again.

Rivals, measured and left out: letting a template drive only while no other engaged, unrefused
template explained the recent samples about as well (within 0.5 sigma) stopped the line from
driving the start of a square, but with twenty templates some other template nearly always
fits as well: valid after 30% of gestures at 0.7-1.4x fell from 0.92 to 0.59 (margin 0.1:
0.73). Checked only before a template is recognised (once valid it stays so): 0.91 -> 0.82 at
margin 0.3 (0.72 at 0.6), while the longest wrong-valid run back to back fell from 11 to 5
samples (median); recognition at 30% of gestures 0.73 -> 0.47.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from behaviors.mop.hmm import TemplateBank

#: The input counts as moving at this many times its template's ``v0`` (a quarter of its median
#: speed): at 1x, the jitter of a puck held still (0.7 mm) moved it on a narrow template (a
#: vertical lift, 1.7 cm of spread across it), and the misfit of those random directions
#: refused the lift during its hold (raise-hold-return progress RMSE max 0.06 -> 0.44).
INPUT_SPEED = 3.0
#: Aligned samples the recent misfit starts from: with one, a single jitter spike (misfit 1)
#: read 0.5 and refused.
MISFIT_PRIOR = 3.0
#: Samples over which directions are measured (template and performance alike): over 2, the
#: jitter of a still puck read as motion.
DIRECTION_LAG = 4


def template_velocities(templates: Mapping[str, np.ndarray], bank: TemplateBank,
                        lag: int) -> tuple[np.ndarray, np.ndarray]:
    """Per state of ``bank``, the template's velocity over ``lag`` recorded samples in its own
    standardised units (states, d), and per template a quarter of its median moving speed (K,)
    (below that a state counts as still: holds and eased starts)."""
    k = len(bank.names)
    v0 = np.ones(k)
    parts = []
    for i, name in enumerate(bank.names):
        a = np.asarray(templates[name], dtype=float).reshape(len(templates[name]), -1)
        v = (a - a[np.maximum(np.arange(len(a)) - lag, 0)]) / bank.scale[i]
        speed = np.sqrt(np.sum(v * v, axis=1))
        moving = speed[speed > 1e-9]
        v0[i] = 0.25 * float(np.median(moving)) if moving.size else 1.0
        src = bank.source[bank.starts[i]:bank.starts[i] + bank.lengths[i]]
        keep = np.rint(src * (len(a) - 1)).astype(int)
        parts.append(v[keep])
    return np.concatenate(parts), v0


def unit_directions(velocity: np.ndarray, v0: np.ndarray,
                    bank: TemplateBank) -> tuple[np.ndarray, np.ndarray]:
    """Unit directions of the states' velocities (states, d; zeros where still) and which
    states move (faster than their template's ``v0``)."""
    speed = np.sqrt(np.sum(velocity * velocity, axis=1))
    moving = speed >= np.repeat(v0, bank.lengths)
    unit = np.where(moving[:, None], velocity / np.maximum(speed, 1e-12)[:, None], 0.0)
    return unit, moving


def direction_misfit(velocity: np.ndarray, direction: np.ndarray, moving: np.ndarray,
                     v0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per template: ``1 - |cos|`` between the input's ``velocity`` (K, d: over the same lag,
    in each template's standardised units and size) and the template's unit ``direction`` at the
    followed state (K, d), and the weight of that evidence (K,): 1 when both move (the template
    state ``moving``, the input at least :data:`INPUT_SPEED` x ``v0``), else 0."""
    speed = np.sqrt(np.einsum("kd,kd->k", velocity, velocity))
    w = (moving & (speed >= INPUT_SPEED * v0)).astype(float)
    cos = np.abs(np.einsum("kd,kd->k", velocity, direction)) / np.maximum(speed, 1e-12)
    return 1.0 - np.minimum(cos, 1.0), w


def update_misfit(misfit: np.ndarray, weight: np.ndarray, e: np.ndarray, w: np.ndarray,
                  decay: np.ndarray | float, new: np.ndarray) -> np.ndarray:
    """Fold one sample's misfit ``e`` of weight ``w`` into the recent sums (in place; templates
    ``new`` start afresh) and return the recent misfit, with a prior of :data:`MISFIT_PRIOR` aligned samples."""
    misfit[new] = 0.0
    weight[new] = 0.0
    misfit *= decay
    misfit += w * e
    weight *= decay
    weight += w
    return misfit / (weight + MISFIT_PRIOR)


class Validity:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: refusal."""

    def _direction(self, x: np.ndarray, gi: np.ndarray, new: np.ndarray) -> np.ndarray:
        """Recent direction misfit per template (see the module docstring), averaged over
        ``direction_memory`` samples of motion. Judged on
        paths only (``invariance`` scale or offset): on features of unknown geometry (a puck's
        dx, dy and heading followed as recorded) a slow twist then push was refused for 35% of
        its second half."""
        v = self._velocity[None, :] / self.bank.scale
        if self.invariance == "scale":
            v = v / self._size[:, None]
        e, w = direction_misfit(v, self._tdir[gi], self._tmoving[gi], self._dv0)
        if self.invariance == "none":
            w[:] = 0.0
        return update_misfit(self._misfit, self._misfit_weight, e, w, self._ddecay, new)

    def _refuse(self, dist2: np.ndarray, misfit: np.ndarray) -> None:
        """Refusal with hysteresis from the recent squared distances (sigma units) and direction
        misfits (in place on ``_refused``)."""
        self._refused |= (dist2 > self._null2) | (misfit > self._dlimit)
        self._refused &= ~((dist2 < self._accept2) & (misfit < self._daccept))
