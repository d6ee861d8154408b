"""What a follower answers after each sample (:class:`FollowState`), and its input error."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator, Mapping, Sequence

from tabletop.frames import InputError


class SampleError(InputError):
    """A live sample has the wrong shape for the template set."""


class ByName(Mapping[str, float]):
    """Read-only map from template name to its value, over values kept in template order: a
    state's per-template maps cost nothing to build (a dictionary of 100 templates took ~9 us,
    four per follower per sample)."""

    __slots__ = ("_index", "_values")

    def __init__(self, index: Mapping[str, int], values: Sequence[float]) -> None:
        self._index, self._values = index, values

    def __getitem__(self, name: str) -> float:
        return self._values[self._index[name]]

    def __iter__(self) -> Iterator[str]:
        return iter(self._index)

    def __len__(self) -> int:
        return len(self._index)

    def __repr__(self) -> str:
        return repr(dict(self.items()))


@dataclass(frozen=True)
class FollowState:
    """The follower's answer after one sample.

    ``best``: the most probable template; ``progress`` (0..1) and ``variance`` (progress units
    squared) of ``best``; ``probabilities``: per template, summing to 1; ``progress_by``: per
    template; ``valid``: the performance matches ``best`` well enough to drive a character;
    ``loglik``: recent mean per-sample log-likelihood of ``best`` (its own units);
    ``distance``: that log-likelihood as an RMS distance in ``sigma`` units per feature;
    ``restarted``: a new performance of ``best`` began at this sample; ``likely``: while the
    input moves (not still; before any template is engaged, once it left the anchor by
    the follower's ``hint_onset`` sigmas), the templates not refused, likeliest first, as (name,
    probability, progress): early feedback, whether or not anything is valid yet; ``scale_by``: each
    template's estimated performance size (1 = as recorded); ``holding``: ``best`` is where its
    template holds still (or at its end), so a performer resting there is holding the action.
    """

    best: str
    progress: float
    variance: float
    probabilities: Mapping[str, float]
    progress_by: Mapping[str, float]
    valid: bool
    loglik: float
    distance: float = 0.0
    restarted: bool = False
    loglik_by: Mapping[str, float] = field(default_factory=dict)
    likely: tuple[tuple[str, float, float], ...] = ()
    scale_by: Mapping[str, float] = field(default_factory=dict)
    holding: bool = False
