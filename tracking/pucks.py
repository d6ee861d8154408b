"""The puck tracker: marker measurements -> stable pucks with identity, smoothing and coasting.

Per marker id one track. Each update:

1. association: of the measurements of an id, the one nearest the track's prediction is taken
   (a duplicate id in one frame is resolved by consistency with the track, not by order); one
   outside the gate (``gate_m`` plus ``max_speed`` times the time since the puck was last seen)
   is an outlier and ignored, unless it is seen again at the same place ``confirm_frames`` times
   in a row (the puck was really moved there);
2. filtering: the One Euro filter (tracking.filters) on position and on the unwrapped heading;
3. occlusion: a track whose source delivers a frame without it is predicted with a decaying
   constant velocity and reported ``coasting`` for up to ``coast_s``, then dropped. A hidden puck
   is never ``seen``. When it comes back, its measured pose (``raw_*``) is reported at once and
   its smoothed pose (``x``, ``y``, ``angle``) moves at most ``reacquire_step_m`` per update
   toward it;
4. velocity (``vx``, ``vy``) and angular velocity (``omega``) from the measurements, low-passed.

Units: whatever the measurements use, table metres by default; ``units_per_metre`` converts the
metre-valued settings (gate, speeds, steps, beta) when the tracker runs on pixels. Angles in
radians, times in seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Sequence

import numpy as np

from tabletop.frames import Observation, Puck, PuckMeasurement, wrap_angle
from tracking.filters import OneEuroFilter, smoothing_factor


@dataclass(frozen=True)
class TrackerSettings:
    """Tracker options; lengths in metres (scaled by ``units_per_metre``), times in seconds.

    One Euro: ``min_cutoff`` (Hz), ``beta`` (per m/s of speed, Hz), ``d_cutoff`` (Hz) for
    position; ``angle_min_cutoff``, ``angle_beta`` (per rad/s), for the heading. ``smooth``:
    False reports the measured pose as the puck's pose (no filter). ``coast_s``: how long a lost
    puck is predicted; ``coast_decay_s``: time constant of its fading velocity.
    ``reacquire_step_m``/``reacquire_step_rad``: the most the smoothed pose moves per update
    toward a puck that reappears. ``gate_m``, ``max_speed``: outlier gate radius
    ``gate_m + max_speed * (time since seen)``; ``confirm_frames``: consistent far sightings
    that relocate a puck. ``velocity_cutoff_hz``: low-pass of the velocity estimate.
    ``stale_s``: a puck whose source has delivered nothing for that long is coasting.
    """

    min_cutoff: float = 0.2
    beta: float = 40.0
    d_cutoff: float = 0.5
    angle_min_cutoff: float = 0.3
    angle_beta: float = 2.0
    smooth: bool = True
    coast_s: float = 0.5
    coast_decay_s: float = 0.3
    reacquire_step_m: float = 0.01
    reacquire_step_rad: float = 0.2
    gate_m: float = 0.06
    max_speed: float = 3.0
    confirm_frames: int = 2
    velocity_cutoff_hz: float = 5.0
    stale_s: float = 0.25
    units_per_metre: float = 1.0


def decayed_travel(v: np.ndarray | float, dt: float, decay_s: float) -> np.ndarray | float:
    """Distance travelled in ``dt`` seconds from velocity ``v`` decaying exponentially with time
    constant ``decay_s``: v * decay_s * (1 - exp(-dt / decay_s))."""
    if dt <= 0.0:
        return v * 0.0
    return v * decay_s * (1.0 - math.exp(-dt / decay_s))


@dataclass
class _Track:
    id: int
    source: str
    t: float                       # time of the last accepted measurement
    meas: np.ndarray               # last measured x, y, unwrapped angle
    out: np.ndarray                # reported (smoothed) x, y, unwrapped angle
    pos_filter: OneEuroFilter
    angle_filter: OneEuroFilter
    vel: np.ndarray = field(default_factory=lambda: np.zeros(2))
    omega: float = 0.0
    state: str = "seen"
    lost_t: float | None = None    # when coasting began
    anchor: np.ndarray | None = None  # reported pose when coasting began
    reacquiring: bool = False
    candidate: np.ndarray | None = None
    candidate_count: int = 0
    coast_t: float = 0.0           # time of the newest coasting prediction


class PuckTracker:
    """Fuses observations into tracked pucks (see the module docstring).

    ``update(observations, t)`` takes the newest observation of every source (the same object
    again when a source has nothing new) and returns the pucks, sorted by id. ``step(measurements,
    t, source)`` does the same for bare measurements of one source (one camera frame).
    """

    def __init__(self, settings: TrackerSettings | None = None) -> None:
        self.s = settings or TrackerSettings()
        self.tracks: dict[int, _Track] = {}
        self._seen_seq: dict[str, int] = {}
        self._pucks: tuple[Puck, ...] = ()

    # ------------------------------------------------------------------ public
    def update(self, observations: Sequence[Observation], t: float) -> tuple[Puck, ...]:
        """New observations (by source and seq) are applied; then lost pucks expire at ``t``."""
        fresh = []
        for obs in observations:
            if self._seen_seq.get(obs.source) == obs.seq:
                continue
            self._seen_seq[obs.source] = obs.seq
            fresh.append(obs)
        for obs in sorted(fresh, key=lambda o: o.t):
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
        """Predicted (x, y) of every track at time ``t`` (for region-of-interest detection)."""
        out = {}
        for pid, tr in self.tracks.items():
            p = tr.meas[:2] + decayed_travel(tr.vel, t - tr.t, self.s.coast_decay_s)
            out[pid] = (float(p[0]), float(p[1]))
        return out

    def reset(self) -> None:
        self.tracks.clear()
        self._seen_seq.clear()
        self._pucks = ()

    # ------------------------------------------------------------------ internals
    def _gate(self, tr: _Track, t: float) -> float:
        u = self.s.units_per_metre
        return u * (self.s.gate_m + self.s.max_speed * max(t - tr.t, 0.0))

    def _apply(self, measurements: Sequence[PuckMeasurement], t: float, source: str,
               complete: bool) -> None:
        by_id: dict[int, list[PuckMeasurement]] = {}
        for m in measurements:
            if all(math.isfinite(v) for v in (m.x, m.y, m.angle)):
                by_id.setdefault(int(m.id), []).append(m)
        for pid, ms in by_id.items():
            tr = self.tracks.get(pid)
            if tr is None:
                best = max(ms, key=lambda m: m.quality)  # nothing to be consistent with yet
                self.tracks[pid] = self._new_track(best, source)
            elif not self._associate(tr, ms, source):
                self._miss(tr, ms[0].t if ms else t)
        if complete:
            for pid, tr in self.tracks.items():
                if pid not in by_id and tr.source == source:
                    self._miss(tr, t)

    def _new_track(self, m: PuckMeasurement, source: str) -> _Track:
        s, u = self.s, self.s.units_per_metre
        pos = OneEuroFilter(s.min_cutoff, s.beta / u, s.d_cutoff)
        ang = OneEuroFilter(s.angle_min_cutoff, s.angle_beta, s.d_cutoff)
        meas = np.array([m.x, m.y, m.angle], float)
        pos.reset(meas[:2], m.t)
        ang.reset(meas[2:], m.t)
        return _Track(m.id, source, m.t, meas, meas.copy(), pos, ang)

    def _associate(self, tr: _Track, ms: list[PuckMeasurement], source: str) -> bool:
        """Take the measurement consistent with the track; False if every one is an outlier."""
        t = ms[0].t
        pred = tr.meas[:2] + decayed_travel(tr.vel, t - tr.t, self.s.coast_decay_s)
        dists = [math.hypot(m.x - pred[0], m.y - pred[1]) for m in ms]
        k = int(np.argmin(dists))
        if dists[k] <= self._gate(tr, t):
            tr.candidate, tr.candidate_count = None, 0
            self._accept(tr, ms[k], source, relocated=False)
            return True
        # Far from the track: a false detection, unless it keeps appearing at the same place.
        m = ms[k]
        p = np.array([m.x, m.y])
        u = self.s.units_per_metre
        if tr.candidate is not None and np.hypot(*(p - tr.candidate)) <= u * self.s.gate_m:
            tr.candidate_count += 1
        else:
            tr.candidate_count = 1
        tr.candidate = p
        if tr.candidate_count >= self.s.confirm_frames:
            tr.candidate, tr.candidate_count = None, 0
            self._accept(tr, m, source, relocated=True)
            return True
        return False

    def _accept(self, tr: _Track, m: PuckMeasurement, source: str, relocated: bool) -> None:
        s, u = self.s, self.s.units_per_metre
        t = m.t
        dt = t - tr.t
        angle = tr.meas[2] + wrap_angle(m.angle - tr.meas[2])  # unwrapped
        meas = np.array([m.x, m.y, angle])
        returning = tr.state == "coasting" or relocated
        if dt > 0.0:
            if relocated:
                tr.vel[:] = 0.0
                tr.omega = 0.0
            else:
                a = float(smoothing_factor(s.velocity_cutoff_hz, dt))
                if returning:  # no momentum carried through an occlusion
                    tr.vel[:], tr.omega, a = 0.0, 0.0, 1.0 if dt < 0.1 else a
                tr.vel += a * ((meas[:2] - tr.meas[:2]) / dt - tr.vel)
                tr.omega += a * ((meas[2] - tr.meas[2]) / dt - tr.omega)
        if returning:
            tr.pos_filter.reset(meas[:2], t)
            tr.angle_filter.reset(meas[2:], t)
            tr.reacquiring = True
            target = meas.copy()
        elif s.smooth:
            target = np.concatenate([tr.pos_filter.filter(meas[:2], t),
                                     tr.angle_filter.filter(meas[2:], t)])
        else:
            target = meas.copy()
        if tr.reacquiring:
            # Keep the smoothed angle on the same branch as the measurement.
            tr.out[2] = target[2] + wrap_angle(tr.out[2] - target[2])
            step = target - tr.out
            d = float(np.hypot(step[0], step[1]))
            lim = s.reacquire_step_m * u
            if d > lim:
                step[:2] *= lim / d
            step[2] = float(np.clip(step[2], -s.reacquire_step_rad, s.reacquire_step_rad))
            tr.out = tr.out + step
            tr.reacquiring = d > lim or abs(target[2] - tr.out[2]) > 1e-9
            if not tr.reacquiring:
                tr.out = target
        else:
            tr.out = target
        tr.meas, tr.t, tr.source = meas, t, source
        tr.state, tr.lost_t, tr.anchor = "seen", None, None

    def _miss(self, tr: _Track, t: float) -> None:
        if tr.state != "coasting":
            tr.state, tr.lost_t, tr.anchor = "coasting", tr.t, tr.out.copy()
        gone = max(t - tr.t, 0.0)
        travel = decayed_travel(tr.vel, gone, self.s.coast_decay_s)
        turn = decayed_travel(tr.omega, gone, self.s.coast_decay_s)
        tr.out = tr.anchor + np.array([travel[0], travel[1], turn])
        tr.coast_t = max(t, tr.t)

    def _expire(self, t: float) -> None:
        for tr in self.tracks.values():
            if tr.state == "seen" and t - tr.t > self.s.stale_s:
                self._miss(tr, t)  # its source went quiet: no longer seen
        for pid in [p for p, tr in self.tracks.items() if t - tr.t > self.s.coast_s]:
            del self.tracks[pid]

    def _puck(self, tr: _Track) -> Puck:
        if tr.state == "coasting":
            k = math.exp(-max(tr.coast_t - tr.t, 0.0) / self.s.coast_decay_s)
            vx, vy, omega = tr.vel[0] * k, tr.vel[1] * k, tr.omega * k
        else:
            vx, vy, omega = tr.vel[0], tr.vel[1], tr.omega
        return Puck(tr.id, float(tr.out[0]), float(tr.out[1]), wrap_angle(float(tr.out[2])),
                    float(vx), float(vy), float(omega), tr.state,  # type: ignore[arg-type]
                    raw_x=float(tr.meas[0]), raw_y=float(tr.meas[1]),
                    raw_angle=wrap_angle(float(tr.meas[2])))
