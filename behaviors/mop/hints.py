"""When a performer's likeliest actions are shown faintly (early feedback).

A performer's hints show from the sample its input leaves the rest radius where it stood
(``rest_radius``, 3 mm for a puck: 4.3 standard deviations of the tracker's 0.7 mm jitter) until
it has stayed within that radius for :data:`HINT_MOVED` samples, but only once it stood still
that long first: a puck just put down, whose rest point is the mean of a few jittered samples,
crossed it by jitter alone (4 of the first 12 samples of one draw of twelve on the example
installation, hinted at probability 0.77). The followers add their own gate
(``FollowState.likely``: the input not still and, before any template is engaged,
:data:`HINT_ONSET` sigmas from the anchor); a follower alone keeps its engagement onset there
(0.5), as nothing else tells its jitter from a move (0.3 showed hints on a still lead-in,
``tests/mop/test_quality.py``). A stream's columns tell no stillness: its hints are its followers'
alone, at their engagement onset. Recognition never reads the hints.

Measured on the example installation (``examples/mop.yaml``, 60 Hz, 0.7 mm jitter, its eleven
puck/gesture pairs after a 1 s rest): the first hint comes at progress 0.083-0.117, the sample
the rest ends or the one after (the puck is 3 mm from its start at 0.083-0.111: these gestures
ease in; 0.097-0.156 with the engagement onset, 0.5, as the followers' gate), steady until the
action drives (no gap), at probability 0.43-0.61 on its first sample. ``HINT_ONSET`` 0 / 0.1 /
0.2: the same first hints at 0 and 0.1 (0.2: 0.083-0.133); gestures hinted later than 0.2 s
after they stopped 7 / 5 / 4 of 11 (at most 7 / 5 / 5 samples). ``HINT_MOVED`` 12 against 24
(``HINT_ONSET`` 0): the same first hints; gestures hinted later than 0.2 s after they stopped 7
against 10 (at most 7 against 21 samples). Unrelated strokes
(``bench.motions.unrelated_motions``, 2 s each, either puck): hints reach probability 1.0 on
every one (mean 0.31-0.73 over the stroke): the probability is the templates' among themselves.

A character is hinted with its actions' probability among all its performer's templates, not
among its own (the example installation, each gesture after a 1 s rest). Renormalised over its
own, the refused left out: its own gestures hinted more (samples hinted with the right action
190 -> 246; the mime on the circle at 0.56, was 0.08), but every character lit up on the others'
gestures (samples hinted 225 -> 1341 of 2033, the one-action bird at 1.0): refusal comes too late
to tell them apart. The same with the top three's membership kept: 225 -> 1245. Shown only while
its actions together are at least as likely as under a uniform prior: right samples 190 -> 126,
the first hint up to 106 samples later (the circle and the figure eight start alike); or each
while at least 0.25 / 0.5 as likely as the likeliest: right samples 160 / 136, the mime's first
hint on the circle at its sample 118 (was 14).
"""

from __future__ import annotations

import numpy as np

#: Sigmas (RMS per feature, each template's spread and size) a stage's followers require the
#: input to lie from the anchor before any template is engaged (their ``hint_onset``).
HINT_ONSET = 0.1
#: Samples an input may stay within its rest radius and still show hints (0.2 s at 60 Hz); as
#: many still samples before a move let the next move show them.
HINT_MOVED = 12


def tells_stillness(performer: object) -> bool:
    """Whether one of ``performer``'s inputs measures how long it stood still (a puck, a
    finger); a stream's columns do not."""
    return any(hasattr(i, "still") for i in performer.inputs)  # type: ignore[attr-defined]


def touch_radius(performer: object) -> float:
    """Twice the rest radius (metres) of ``performer``'s finger, 0 when it has none: a finger
    that touches down starts a stroke, shown once it lies this far from where it touched."""
    from behaviors.mop.inputs import TouchInput
    touch = [i for i in performer.inputs if isinstance(i, TouchInput)]  # type: ignore[attr-defined]
    if not touch or len(performer.inputs) != 1:
        return 0.0
    return 2 * touch[0]._pf.rest_radius  # type: ignore[attr-defined]


class HintGate:
    """One performer's: whether its likeliest actions may be shown this sample.

    An input that goes missing (a puck lifted, no finger) closes the gate and forgets its calm:
    a puck put down must stand still :data:`HINT_MOVED` samples before a move shows hints, as
    the jitter about its new rest point crosses the rest radius (were the lift counted as a
    rest, 7 of 8 draws of a puck put down still would be hinted, 4-12 samples at 0.72-0.92). A
    finger's touch-down starts a stroke: until it has stood still that long, it shows hints
    once it lies ``touch`` metres (twice its rest radius) from where it touched down, which
    its jitter (0.7 mm) does not reach."""

    def __init__(self, measured: bool = True, touch: float = 0.0) -> None:
        self.shown = False
        self.measured = measured   # the input tells its stillness (a puck, a finger; no stream)
        self.touch = touch         # a finger's stroke distance from its touch-down (0: none)
        self._calm = False   # it stood still HINT_MOVED samples (or rested) since it last moved
        self._down = False   # a finger touched down and has not yet stood still

    def update(self, resting: bool, still: int, x: np.ndarray | None = None) -> None:
        """``resting``: the input's gesture ended (it rests); ``still``: samples since it last
        left its rest radius (1: it just did); ``x``: this sample's input (NaN: missing).
        Without a measure of stillness, shown whenever the input does not rest (its followers
        keep their own gate)."""
        present = x is None or bool(np.isfinite(x).all())
        if not self.measured:
            self.shown = not resting
        elif not present:
            self.shown, self._calm, self._down = False, False, self.touch > 0
        elif resting or still > HINT_MOVED:
            self.shown, self._calm, self._down = False, True, False
        elif still == 1 and self._calm:
            self.shown, self._calm = True, False
        elif self._down and x is not None and float(np.hypot(*x[:2])) > self.touch:
            self.shown, self._down = True, False


class HintGates:
    """Every performer's :class:`HintGate`, built once (``performers``: name -> performer)."""

    def __init__(self, performers: dict[str, object]) -> None:
        self._gates = {name: HintGate(tells_stillness(p), touch_radius(p))
                       for name, p in performers.items()}

    def update(self, name: str, resting: bool, still: int, x: np.ndarray) -> None:
        """Performer ``name``'s sample (:meth:`HintGate.update`)."""
        self._gates[name].update(resting, still, x)

    def likely(self, name: str, state: object) -> dict[str, float]:
        """The likeliest actions of performer ``name``'s follower ``state`` to show this sample
        (name -> probability; none while its gate is shut)."""
        gate = self._gates.get(name)
        if gate is None or not gate.shown:
            return {}
        return {key: p for key, p, _ in state.likely}  # type: ignore[attr-defined]


def gate_onsets(followers: dict[str, object], performers: dict[str, object]) -> None:
    """Give the followers of performers that tell their stillness the :data:`HINT_ONSET`
    gate (the others keep their engagement onset)."""
    for name, f in followers.items():
        if tells_stillness(performers[name]):
            f.hint_onset = HINT_ONSET  # type: ignore[attr-defined]
