"""The puck tracker: marker measurements -> stable pucks with identity, smoothing and coasting.

Per marker id one track (tracking.track). Each update:

1. association (tracking.matching): of the measurements of an id, the one nearest the track's
   prediction inside the outlier gate is taken; a far one relocates the puck only when read
   again at the same place ``confirm_frames`` times, and of two places read as one id the one
   that moves is the puck. Ids not in ``TrackerSettings.pucks`` (when it names the pucks) are
   no puck;
2. filtering: the One Euro filter (tracking.filters) on position and on the unwrapped heading;
3. occlusion (tracking.coasting): a track whose source delivers a frame without it is
   predicted with a decaying velocity turning at the puck's measured rate of turn and reported
   ``coasting`` for up to ``coast_s``, then dropped. A hidden puck is never ``seen``. When it
   comes back, its measured pose (``raw_*``) is reported at once and its smoothed pose (``x``,
   ``y``, ``angle``) moves at most ``reacquire_step_m`` per update toward it, until a second
   reading confirms it: the next, within ``CONFIRM_GAP_S`` and no faster than ``max_speed``
   from the first, or a relocation. Then it is shown where it is measured;
4. velocity (``vx``, ``vy``) and angular velocity (``omega``): the measurement's own when its
   source measured them (a TUIO sender's), else estimated from the positions, low-passed.

Units: whatever the measurements use, table metres by default; ``units_per_metre`` converts the
metre-valued settings (gate, speeds, steps, beta) when the tracker runs on pixels. Angles in
radians, times in seconds.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Iterable, Sequence

from tabletop.frames import Observation, Puck, PuckMeasurement, wrap_angle
from tracking.coasting import coasting_velocity, miss, predicted, turned
from tracking.filters import one_euro_floats, scale_beta
from tracking.matching import associate
from tracking.reacquire import reacquired
from tracking.track import (CONFIRM_GAP_S, MAX_OMEGA, SPARSE_GAP_S, STILL_SPEED, Track,
                            TrackerSettings, new_track, take_measured_velocity)
from tracking.turning import decayed_travel

__all__ = ["MAX_OMEGA", "PuckTracker", "TrackerSettings"]


class PuckTracker:
    """Fuses observations into tracked pucks (see the module docstring).

    ``update(observations, t)`` takes the newest observation of every source (the same object
    again when a source has nothing new) and returns the pucks, sorted by id. ``step(measurements,
    t, source)`` does the same for bare measurements of one source (one camera frame).
    """

    def __init__(self, settings: TrackerSettings | None = None) -> None:
        self.s = settings or TrackerSettings()
        self.tracks: dict[int, Track] = {}
        self._seen_seq: dict[str, tuple[int, frozenset[int]]] = {}  # seq, puck ids applied
        self._pucks: tuple[Puck, ...] = ()

    # ------------------------------------------------------------------ public
    def update(self, observations: Sequence[Observation], t: float) -> tuple[Puck, ...]:
        """New observations (by source and seq) are applied; then lost pucks expire at ``t`` (s)."""
        fresh = []
        for obs in observations:
            seq, ids = self._seen_seq.get(obs.source, (None, frozenset()))
            if seq == obs.seq:
                # The same frame again, perhaps with pucks a later search added (a camera
                # publishes them at once): only those are new.
                added = tuple(m for m in obs.pucks if m.id not in ids)
                if not added:
                    continue
                obs = dataclasses.replace(obs, pucks=added, complete=False)
            else:
                ids = frozenset()
            self._seen_seq[obs.source] = (obs.seq, ids | {m.id for m in obs.pucks})
            fresh.append(obs)
        for obs in sorted(fresh, key=lambda o: o.t):
            for pid in obs.removed:  # the source says it left: no coasting
                if pid in self.tracks and self.tracks[pid].source == obs.source:
                    del self.tracks[pid]
            self._apply(obs.pucks, obs.t, obs.source, obs.complete)
        self._expire(t)
        self._pucks = tuple(self._puck(tr) for _, tr in sorted(self.tracks.items()))
        return self._pucks

    def step(self, measurements: Iterable[PuckMeasurement], t: float, source: str = "camera"
             ) -> tuple[Puck, ...]:
        """Apply one complete frame of ``measurements`` taken at ``t`` and return the pucks."""
        self._apply(tuple(measurements), t, source, True)
        self._expire(t)
        self._pucks = tuple(self._puck(tr) for _, tr in sorted(self.tracks.items()))
        return self._pucks

    @property
    def pucks(self) -> tuple[Puck, ...]:
        """The pucks of the last update."""
        return self._pucks

    def predict(self, t: float) -> dict[int, tuple[float, float]]:
        """Predicted (x, y) (table metres) of every track at time ``t`` (s), for
        region-of-interest detection.

        Called from camera threads while the loop updates the tracks: the tracks are copied in
        one step (atomic under the GIL) before they are read."""
        return {pid: predicted(self.s, tr, t) for pid, tr in tuple(self.tracks.items())}

    def reset(self) -> None:
        self.tracks.clear()
        self._seen_seq.clear()
        self._pucks = ()

    # ------------------------------------------------------------------ internals
    def _apply(self, measurements: Sequence[PuckMeasurement], t: float, source: str,
               complete: bool) -> None:
        by_id: dict[int, list[PuckMeasurement]] = {}
        named = self.s.pucks
        for m in measurements:
            if named and int(m.id) not in named:
                continue
            if math.isfinite(m.x) and math.isfinite(m.y) and math.isfinite(m.angle):
                by_id.setdefault(int(m.id), []).append(m)
        for pid, ms in by_id.items():
            tr = self.tracks.get(pid)
            if tr is None:
                best = max(ms, key=lambda m: m.quality)  # nothing to be consistent with yet
                self.tracks[pid] = new_track(best, source, self.s)
            elif ms[0].t >= tr.t:  # else older than what the track holds (another source)
                taken = associate(self.s, tr, ms)
                if taken is None:   # every one an outlier
                    miss(self.s, tr, ms[0].t)
                else:
                    self._accept(tr, taken[0], source, relocated=taken[1])
        if complete:
            for pid, tr in self.tracks.items():
                if pid not in by_id and tr.source == source:
                    miss(self.s, tr, t)

    def _accept(self, tr: Track, m: PuckMeasurement, source: str, relocated: bool) -> None:
        s, u = self.s, self.s.units_per_metre
        t = float(m.t)
        dt = t - tr.t
        old = tr.meas
        meas = [float(m.x), float(m.y), old[2] + wrap_angle(m.angle - old[2])]  # angle unwrapped
        # A moving puck seen again within SPARSE_GAP_S (motion blur: read every few frames) is
        # one track seen sparsely, filtered from the coasting prediction, not a return. Four pucks
        # at 720p, nine seeds pooled, shown pose: 12 mm blur at 60 Hz, p95 while seen 308 -> 140
        # mm, overall 325 -> 186 mm; back and forth at 1.5 m/s, 8 ms, median 115 -> 50 mm;
        # 9.6 mm blur at 30 Hz, p95 while seen 65 -> 20 mm; nothing worse beyond twice the
        # seed-to-seed spread. A still puck (chord under 0.05 m/s) that reappears returns: taking
        # it too showed a puck back 6 cm away jumping 36 mm in one update, not reacquire_step_m.
        sparse = (tr.state == "coasting" and not relocated and dt <= SPARSE_GAP_S
                  and math.hypot(*tr.chord) > 0.05 * u)
        returning = (tr.state == "coasting" or relocated) and not sparse
        # A return confirmed by a second reading is shown where it is read. Rendered frames, a
        # puck lifted for 0.3 s and put back 0.14 m away: within 10 mm from its second reading,
        # read every frame (else 12-13 readings, 1 cm each) or every other (else 4-5). One
        # reading alone moves it as before (none of 4,198 readings among hands was false).
        # A moving puck too, once its turn was measured (tracking.turning): a hand over a 0.5
        # m/s puck, 13 readings -> 1. Coasting along the tangent, snapping made pucks read in
        # 8-11% of frames (12-13 mm blur, 60 Hz) worse, overall p95 188 -> 198 mm, nine seeds
        # pooled; coasting on the measured turn, 188 -> 180 mm (74 figures better, 2 worse:
        # back and forth at 1.5 m/s p95 375.2 -> 375.3, 30 Hz hand median 11.248 -> 11.252 mm;
        # read every other frame at 60 Hz, error at the 12th frame after 4.715 -> 4.784 mm).
        confirmed = relocated or (tr.reacquiring and not returning and 0.0 < dt <= CONFIRM_GAP_S
                                  and math.hypot(meas[0] - old[0], meas[1] - old[1])
                                  <= (s.max_speed if tr.steady else STILL_SPEED) * u * dt)
        if sparse and s.smooth and not confirmed:
            tr.pos, tr.ang = tr.out[:2], tr.out[2:]
            if tr.anchor is not None:  # the straight prediction: filtered from the turned
                # one, the filter's speed came out lower and it lagged more (9.6 mm blur, 60
                # Hz, median 6.33 -> 6.36 mm)
                k = decayed_travel(1.0, tr.coast_t - tr.t, s.coast_decay_s)
                tr.pos = [tr.anchor[0] + k * tr.vx, tr.anchor[1] + k * tr.vy]
            tr.reacquiring = False
        if dt > 0.0:
            if relocated:
                tr.vx = tr.vy = tr.omega = 0.0
                tr.rival = None
            else:
                a = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * s.velocity_cutoff_hz * dt))
                pv = tr.chord
                if returning or sparse:  # no momentum carried through an occlusion
                    tr.vx = tr.vy = tr.omega = 0.0
                    a = 1.0 if dt < 0.1 else a
                tr.vspan, tr.vfiltered = dt, not (returning or sparse)
                tr.vx += a * ((meas[0] - old[0]) / dt - tr.vx)
                tr.vy += a * ((meas[1] - old[1]) / dt - tr.vy)
                tr.chord = (tr.vx, tr.vy)
                if sparse:  # the chord, trusted as far as it agrees with the one before: taken
                    # whole, it overshot circles and reversals where 5-13% of frames are read
                    # (12-13 mm blur, overall p95 193 -> 229, 237 -> 273 mm)
                    n, n0 = math.hypot(tr.vx, tr.vy), math.hypot(*pv)
                    c = 1.0
                    if n > 0.0 and n0 > 0.05 * u:
                        c = max(1.0 - math.hypot(tr.vx - pv[0], tr.vy - pv[1]) / n, 0.0)
                    tr.vx, tr.vy = c * tr.vx, c * tr.vy
                tr.omega += a * ((meas[2] - old[2]) / dt - tr.omega)
        turned(s, tr, meas, t, returning or relocated, relocated)
        take_measured_velocity(tr, m, s.max_speed * u)
        if not sparse:
            tr.chord = (tr.vx, tr.vy)
        if returning or confirmed:
            tr.pos, tr.dpos, tr.ang, tr.dang = meas[:2], [0.0, 0.0], meas[2:], [0.0]
            if confirmed and not relocated and dt > 0.0:  # the filter's speed: the chord's
                tr.dpos = [(meas[0] - old[0]) / dt, (meas[1] - old[1]) / dt]
            tr.reacquiring = not confirmed
            target = list(meas)
        elif s.smooth and dt > 0.0:
            if sparse:  # the prior is the prediction shown at coast_t
                dt = max(t - tr.coast_t, 1e-6)
            tr.pos, tr.dpos = one_euro_floats(meas[:2], tr.pos, tr.dpos, dt, s.min_cutoff,
                                              scale_beta(s.beta, u), s.d_cutoff)
            tr.ang, tr.dang = one_euro_floats(meas[2:], tr.ang, tr.dang, dt,
                                              s.angle_min_cutoff, s.angle_beta, s.d_cutoff)
            target = tr.pos + tr.ang
        elif s.smooth:
            target = tr.pos + tr.ang
        else:
            target = list(meas)
        if tr.reacquiring:
            tr.out, tr.gap = reacquired(tr.out, target, tr.gap, returning,
                                        s.reacquire_step_m * u, s.reacquire_step_rad, u)
            tr.reacquiring = tr.out != target
        else:
            tr.out = target
        tr.meas, tr.t, tr.source = meas, t, source
        tr.state, tr.anchor = "seen", None

    def _expire(self, t: float) -> None:
        for tr in self.tracks.values():
            if tr.state == "seen" and t - tr.t > self.s.stale_s:
                miss(self.s, tr, t)  # its source went quiet: no longer seen
        for pid in [p for p, tr in self.tracks.items() if t - tr.t > self.s.coast_s]:
            del self.tracks[pid]

    def _puck(self, tr: Track) -> Puck:
        k, vx, vy = coasting_velocity(self.s, tr)
        return Puck(tr.id, tr.out[0], tr.out[1], wrap_angle(tr.out[2]), vx, vy,
                    tr.omega * k, tr.state,  # type: ignore[arg-type]
                    raw_x=tr.meas[0], raw_y=tr.meas[1], raw_angle=wrap_angle(tr.meas[2]))
