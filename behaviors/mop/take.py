"""A designer's take (MOP 4.1.1): samples of a performer's features at the engine rate, read
against the origin the gesture had when the take began, waiting to be kept or discarded; and the
trim of the stills before and after its gesture."""

from __future__ import annotations

import numpy as np


class Take:
    """A designer's recording of one performer's features (rows at the engine rate)."""

    def __init__(self, performer: str, character: str, t0: float) -> None:
        self.performer, self.character, self.t0 = performer, character, t0
        #: where the performer's gesture started when the take began (features' terms; NaN
        #: where an input had not started one, a finger not yet down: its first sample's):
        #: samples read against a later origin are shifted back to it
        self.origin: np.ndarray | float = 0.0
        self.rows: list[np.ndarray] = []
        self.recording = True
        self.motion_index = 0

    def add(self, x: np.ndarray, origin: np.ndarray | float = 0.0) -> None:
        """Record the sample ``x`` read against ``origin`` (the performer's, features' terms)."""
        if not (self.recording and np.all(np.isfinite(x))):
            return
        self.origin = np.where(np.isfinite(self.origin), self.origin, origin)
        self.rows.append(np.asarray(x + (origin - self.origin), dtype=float))

    def samples(self) -> np.ndarray:
        """The recorded samples (n x d); empty (0 x 0) before the first."""
        return np.vstack(self.rows) if self.rows else np.zeros((0, 0))

    def trim_still(self, units: np.ndarray | None = None,
                   jitter: np.ndarray | None = None, margin: int = 0) -> None:
        """Drop the still samples before the gesture and after it (see :func:`moving_part`)."""
        first, end = moving_part(self.samples(), units, jitter, margin)
        self.rows = self.rows[first:end]


#: A take's sample within this share of the take's extent of its first (last) sample is still:
#: 0.75 mm of a 15 cm gesture. At 0.02 (3 mm, the puck's rest radius) the slow last millimetres of
#: a square went too, and the action ended before a performer's did (valid over 85% of its second
#: half instead of 90%).
STILL_SHARE = 0.005
#: Rows in a row beyond the still radius that make a move (and the rows at each end whose
#: median the stillness is first measured from): one row's jitter is no move. Measured on takes
#: of the six example gestures recorded through the engine with 0-0.8 mm of jitter and 0.1-1.5 s
#: still before and after (as ``tests/mop/test_take.py`` records them): with single rows and
#: the first (last) row as the first reference, 0.5 mm left up to 47 still rows at the start and
#: 30 at the end, 0.8 mm 47 and 47 (medians 5 and 18: start and end trimmed unevenly); runs of 3
#: left up to 2 and 25 at 0.8 mm (an end row's jitter as the reference), with the medians as
#: the first reference 2 and 13; runs of 4: 2 and 2, and at most 2 rows of gesture cut, as
#: without jitter.
MOVED_RUN = 4


def moving_part(samples: np.ndarray, units: np.ndarray | None = None,
                jitter: np.ndarray | None = None, margin: int = 0,
                share: float = STILL_SHARE) -> tuple[int, int]:
    """(first, end) rows of a take's gesture: the still samples before it (the performer waiting
    for the recording to begin) and after it (reaching for the stop) left out but the one where
    it starts and the one where it ends. A sample is still while it is within ``share`` of the
    take's extent of the take's first (last) sample, columns in ``units`` (default: each
    column's range over the take) and each column's difference reduced by its input's
    ``jitter`` (d,, in the inputs' units; none when None), measured from the mean of the still
    samples, and a move is :data:`MOVED_RUN` rows beyond it in a row; ``margin`` more samples
    are kept at each end. Without the jitter allowance a 2 s
    loop tracked with 0.3 mm of jitter and still 0.3 s at each end kept 71-78 of its 61 samples
    at 30 Hz (148-155 of 121 at 60 Hz; with the speed feature nothing was trimmed); with it 61
    (121; 62 and 123 with the speed feature). A raw camera's 0.8 mm is beyond it (61-122 of 61)
    with single rows as moves; see :data:`MOVED_RUN`.
    Left in, a designer who waited 0.3 s before and after each
    of five gestures made actions whose progress stopped at 0.83-0.89 when the gesture was done
    and whose held end kept them driving while the puck rested: played back at 0.5-2x speed and
    0.6-1.5x size, 24 of 35 were recognised at 60% of them and 599 of 4416 resting ticks drove
    a character; with the stills left out 32 of 35 and 84 (as with takes that had none). A take
    where nothing moved keeps one sample."""
    n = len(samples)
    if n < 2:
        return 0, n
    x = np.asarray(samples, dtype=float)
    u = np.ptp(x, axis=0) if units is None else np.asarray(units, dtype=float)
    z = x / np.where(u > 0, u, 1.0)
    extent = max(float(np.linalg.norm(z - z[0], axis=1).max()),
                 float(np.linalg.norm(z - z[-1], axis=1).max()))
    if extent == 0.0:
        return 0, 1
    r = share * extent
    allow = 0.0 if jitter is None else np.asarray(jitter, dtype=float) / np.where(u > 0, u, 1.0)

    run = min(MOVED_RUN, n)

    def moved(ref: np.ndarray, last: bool = False) -> np.ndarray:
        """Rows starting (``last``: ending) a run of ``run`` rows away from ``ref``."""
        out = np.linalg.norm(np.maximum(np.abs(z - ref) - allow, 0.0), axis=1) > r
        runs = np.flatnonzero(np.convolve(out, np.ones(run, dtype=int), "valid") == run)
        return runs + (run - 1) * last
    away = moved(np.median(z[:run], axis=0))
    left = moved(np.median(z[n - run:], axis=0), last=True)
    # again from the still samples' mean: one sample's jitter doubles the spread
    for _ in range(2):
        if len(away) == 0 or len(left) == 0:
            break
        away = moved(z[:max(1, int(away[0]))].mean(axis=0))
        left = moved(z[min(int(left[-1]) + 1, n - 1):].mean(axis=0), last=True)
    if len(away) == 0 or len(left) == 0:   # every difference within the jitter
        return 0, 1
    first = max(0, int(away[0]) - 1 - margin)
    end = min(n, int(left[-1]) + 2 + margin)
    return first, max(end, first + 1)


def free_take_number(taken: set[str], n: int = 1) -> int:
    """The first ``n`` or later whose ``takeN`` is none of the names ``taken``."""
    while f"take{n}" in taken:
        n += 1
    return n
