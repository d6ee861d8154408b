"""The follower's memory for its validity rules (:mod:`behaviors.mop.validity`): the followed
states, samples and sizes of the last :data:`~behaviors.mop.tempo.TEMPO_SAMPLES`, and the
two rules read from them, the tempo of a new action and the input running on past a template's
path while its progress lags (:mod:`behaviors.mop.overrun`). A follower group applies the same
rules to its members, compiled, in :mod:`behaviors.mop.member_validity`.
"""

from __future__ import annotations

import math

import numpy as np

from behaviors.mop import bends, halts, overrun, speed_profile, tempo


class Validity:
    """Mixin of :class:`~behaviors.mop.follower.ActionFollower`: the tempo of a new action
    (:func:`~behaviors.mop.tempo.slow_take`) and the overrun of its path."""

    def _slow_take(self, k: int, g: np.ndarray, x: np.ndarray,
                   samples: int | None = None) -> tuple[bool, bool]:
        """Template ``k`` (followed states ``g``, bank index) is taken too slowly by sample ``x``
        (:func:`~behaviors.mop.tempo.slow_take`) against the oldest of the last
        :data:`~behaviors.mop.tempo.TEMPO_SAMPLES` samples, or its first state at the anchor
        where that one precedes the attempt (:func:`~behaviors.mop.tempo.before_attempt`;
        ``samples``: the attempt's with this one, by default those of the shape sums); and
        whether the input hovers meanwhile (:func:`~behaviors.mop.tempo.crawl_run`; not yet
        whether ``k`` drove)."""
        if tempo.LEAST_TEMPO <= 0 or len(self._tempo_past) < tempo.TEMPO_SAMPLES:
            return False, False
        then, x0, _ = self._tempo_past[0]
        was = float(then[k])
        n = self._shape_n if samples is None else samples
        span = float(tempo.TEMPO_SAMPLES)
        if tempo.before_attempt(float(n)):
            # (... over the attempt's own samples: tempo.span)
            x0, was, span = self._anchor, 0.0, tempo.span(float(n))
        r = (x - x0) / (self.bank.scale[k] * self._size[k])
        moved = math.sqrt(float(np.mean(r * r)))
        advance = float(g[k] - self.bank.starts[k] - was)
        onset = self.onset * self.sigma
        hovers = moved < onset and abs(advance) < tempo.LEAST_TEMPO * tempo.TEMPO_SAMPLES
        return tempo.slow_take(advance, moved, onset, span), hovers

    def _remember_tempo(self, states: np.ndarray, x: np.ndarray) -> None:
        """Keep the followed ``states`` (K,), sample ``x`` and sizes of the last
        :data:`~behaviors.mop.tempo.TEMPO_SAMPLES`."""
        self._tempo_past.append((states, x, self._size.copy()))
        if len(self._tempo_past) > tempo.TEMPO_SAMPLES:
            del self._tempo_past[0]

    def _overruns(self, k: int, g: np.ndarray, x: np.ndarray, progress: float) -> bool:
        """Whether sample ``x`` runs on past template ``k``'s path while its progress lags
        (:func:`behaviors.mop.overrun.overruns`; ``g``: followed states, bank index;
        ``progress``: the action's as shown, 0..1, as the group reads it), against
        the samples, followed states and sizes the tempo keeps (:meth:`_remember_tempo`);
        with "scale" invariance only (where no size is estimated, a performance at another size
        is off its path by its size: an "offset" member at 1.3x lost 16 of 59 valid ticks).
        Keeps which template overran (``_overran_k``, -1: none) for the next sample's ``held``."""
        back = max(overrun.PACE_SAMPLES, overrun.RISE_SAMPLES)
        held, self._overran_k = self._overran_k == k, -1
        if self.invariance != "scale" or len(self._tempo_past) < back:
            return False
        b = self.bank
        lo = int(b.starts[k])
        g_pace, x_pace, s_pace = self._tempo_past[-overrun.PACE_SAMPLES]
        g_rise, x_rise, _ = self._tempo_past[-overrun.RISE_SAMPLES]
        # (its size's growth spares nothing while the input goes on straight: bends.unspared)
        j = int(g[k])
        at = float(b.source[j] + (g[k] - j) * (b.source[min(j + 1, lo + int(b.lengths[k]) - 1)]
                                               - b.source[j]))
        straight = (self._turn is not None and self._waits[j] > 0.0
                    and bends.unspared(self._turn_in, at))
        out = bool(overrun.overruns(
            b.means, self._arc, lo, int(b.lengths[k]), 0, b.scale[k], self._no_offset,
            self._first_z[k], self._anchor, x, x_rise, x_pace, float(g[k] - lo),
            float(g_rise[k]), float(g_pace[k]), float(self._size[k]), float(s_pace[k]),
            self.sigma ** 2 * self.dim, float(self.dim), held, not straight))
        self._overran_k = k if out else -1
        # ... nor while it waits where its template slows and the input keeps its speed, at this
        # sample and the one before (speed_profile.outpaces; not counted as an overrun), or
        # the input goes on off the way it turns (speed_profile.turns_on, this sample alone)
        if out or len(self._tempo_past) < speed_profile.BACK + 1:
            return out
        then, x_then, _ = self._tempo_past[-1]
        if self._outpaces(k, g[k] - lo, x, 0) and self._outpaces(k, then[k], x_then, 1):
            return True
        past = self._tempo_past
        # ... nor at its start while the input quickens where its template slows
        # (speed_profile.quickens, this sample alone)
        if speed_profile.quickens(
                b.means, lo, int(b.lengths[k]), 0, b.scale[k], self._no_offset,
                self._first_z[k], self._anchor, x, past[-speed_profile.RECENT][1],
                past[-speed_profile.BACK][1], float(g[k] - lo), progress, float(self._size[k]),
                float(past[-1][2][k]), self.sigma):
            return True
        return bool(speed_profile.turns_on(
            b.means, lo, int(b.lengths[k]), 0, b.scale[k], self._no_offset, self._first_z[k],
            self._anchor, x, past[-speed_profile.RECENT][1], past[-speed_profile.BACK][1],
            float(g[k] - lo), float(self._size[k]), float(past[-1][2][k]), self.sigma))

    def _outpaces(self, k: int, g: float, x: np.ndarray, ago: int) -> bool:
        """:func:`behaviors.mop.speed_profile.outpaces` for template ``k`` (bank index) at the
        sample ``ago`` samples back (``x``; ``g``: its followed state, from the first), against
        the samples the tempo keeps (:meth:`_remember_tempo`)."""
        b, past = self.bank, self._tempo_past
        lo = int(b.starts[k])
        return bool(speed_profile.outpaces(
            b.means, lo, int(b.lengths[k]), 0, b.scale[k], self._no_offset,
            self._first_z[k], self._anchor, x, past[-speed_profile.RECENT - ago][1],
            past[-speed_profile.BACK - ago][1], float(g),
            float(past[-speed_profile.STALL_SAMPLES - ago][0][k]),
            float(past[-1 - ago][2][k] if ago else self._size[k]), self.sigma))

    def _halts(self, k: int, g: float, progress: float, x: np.ndarray) -> bool:
        """:func:`behaviors.mop.halts.halts` for template ``k`` (bank index) at sample ``x``, the
        last the tempo keeps (:meth:`_remember_tempo`; ``g``: its followed state, from the
        first, at ``progress``); with "scale" invariance only, as :meth:`_overruns`."""
        b, past = self.bank, self._tempo_past
        if self.invariance != "scale" or len(past) < halts.BACK + 1:
            return False
        return bool(halts.halts(
            b.means, int(b.starts[k]), int(b.lengths[k]), 0, b.scale[k], self._units, x,
            past[-1 - halts.RECENT][1], past[-1 - halts.BACK][1], float(g), float(progress),
            float(self._size[k]), self.sigma))
