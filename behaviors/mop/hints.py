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
"""

from __future__ import annotations

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


class HintGate:
    """One performer's: whether its likeliest actions may be shown this sample."""

    def __init__(self, measured: bool = True) -> None:
        self.shown = False
        self.measured = measured   # the input tells its stillness (a puck, a finger; no stream)
        self._calm = False   # it stood still HINT_MOVED samples (or rested) since it last moved

    def update(self, resting: bool, still: int) -> None:
        """``resting``: the input's gesture ended (it rests); ``still``: samples since it last
        left its rest radius (1: it just did). Without a measure of stillness, shown whenever
        the input does not rest (its followers keep their own gate)."""
        if not self.measured:
            self.shown = not resting
        elif resting or still > HINT_MOVED:
            self.shown, self._calm = False, True
        elif still == 1 and self._calm:
            self.shown, self._calm = True, False
