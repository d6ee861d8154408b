"""The puck tracker: marker measurements -> stable pucks with identity, smoothing and coasting.

Per marker id one track. Each update:

1. association: of the measurements of an id, the one nearest the track's prediction is taken
   (a duplicate id in one frame is resolved by consistency with the track, not by order); one
   outside the gate (``gate_m`` plus ``max_speed`` times the time since the puck was last seen)
   is an outlier and ignored, unless it is seen again at the same place ``confirm_frames`` times
   in a row (the puck was really moved there), but not a still place while the track was moving.
   Far readings are followed as the track's rival (tracking.rivals): a rival that moves while
   the track lies still is the puck, and the place left is a print. Ids not in
   ``TrackerSettings.pucks`` (when it names the pucks) are no puck;
2. filtering: the One Euro filter (tracking.filters) on position and on the unwrapped heading;
3. occlusion: a track whose source delivers a frame without it is predicted with a decaying
   velocity turning at the puck's measured rate of turn (tracking.turning) and reported
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
from dataclasses import dataclass
from typing import Iterable, Sequence

from tabletop.frames import Observation, Puck, PuckMeasurement, wrap_angle
from tracking.filters import one_euro_floats, scale_beta
from tracking.reacquire import reacquired
from tracking.rivals import Rival, follow, screened
from tracking.turning import (TURN_SPEED, decayed_travel, extend_trail, led_velocity, turn_sample,
                              turned_travel, turned_velocity)

MAX_OMEGA = 8.0 * math.pi   # rad/s: 4 turns a second, faster than a hand turns a puck
STILL_SPEED = 0.05  # m/s: a puck moving slower between two readings is lying still
SPARSE_GAP_S = 0.2  # s: a puck seen again this soon is one track, seen sparsely (motion blur)
CONFIRM_GAP_S = 0.07  # s: a second reading this soon after a return confirms it (2 frames at 30 Hz)


@dataclass(frozen=True)
class TrackerSettings:
    """Tracker options; lengths in metres (scaled by ``units_per_metre``), times in seconds.

    One Euro: ``min_cutoff`` (Hz), ``beta`` (per m/s of speed, Hz), ``d_cutoff`` (Hz) for
    position; ``angle_min_cutoff``, ``angle_beta`` (per rad/s), for the heading. ``smooth``:
    False reports the measured pose as the puck's pose (no filter). ``coast_s``: how long a lost
    puck is predicted; ``coast_decay_s``: time constant of its fading velocity.
    ``reacquire_step_m``/``reacquire_step_rad``: the most the smoothed pose moves per update
    toward a puck that reappears, until a second reading confirms it. ``gate_m``,
    ``max_speed``: outlier gate radius ``gate_m + max_speed * (time since seen)``;
    ``confirm_frames``: consistent far sightings that relocate a puck.
    ``velocity_cutoff_hz``: low-pass of the velocity estimate.
    ``stale_s``: a puck whose source has delivered nothing for that long is coasting.
    ``pucks``: the ids of the pucks on the table; a reading of another id (a print, a stray
    marker) is no puck. Empty: every id read is a puck.
    """

    min_cutoff: float = 0.2
    beta: float = 40.0
    d_cutoff: float = 0.5
    angle_min_cutoff: float = 0.3
    # A turning puck's heading lags about 1 / (2 pi angle_beta) rad. Rendered frames, pucks
    # turning 0.5-4 turns a second, median lag at 60 / 30 Hz for angle_beta 2: 2.4-3.9 / 2.9-4.2
    # deg; 4: 1.5-2.1 / 1.7-2.2; 6: 1.1-1.5 / 1.2-1.5; 8: 0.9-1.1 / 1.0-1.2. But the shown
    # heading's frame-to-frame jitter (SD of its error's second difference) on a puck turning
    # 0.05 turns a second grows with it: 0.053 / 0.138, 0.069 / 0.181, 0.079 / 0.209, 0.087 /
    # 0.230 deg; a still puck's SD 0.0037 / 0.0080, 0.0037 / 0.0081, 0.0039 / 0.0082, 0.0042 /
    # 0.0084 deg. No beta lowers the lag without raising that jitter: kept at 2.
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
    pucks: tuple[int, ...] = ()


@dataclass
class _Track:
    """One puck's state; poses are [x, y, unwrapped angle] lists of floats."""

    id: int
    source: str
    t: float                       # time of the last accepted measurement
    meas: list[float]              # last measured pose
    out: list[float]               # reported (smoothed) pose
    pos: list[float]               # One Euro state: filtered x, y and their derivative
    dpos: list[float]
    ang: list[float]               # One Euro state: filtered angle and its derivative
    dang: list[float]
    vx: float = 0.0
    vy: float = 0.0
    omega: float = 0.0
    state: str = "seen"
    anchor: list[float] | None = None  # reported pose when coasting began
    reacquiring: bool = False
    # shown minus measured pose while reacquiring
    gap: list[float] = dataclasses.field(default_factory=lambda: [0.0, 0.0, 0.0])
    candidate: tuple[float, float] | None = None
    candidate_count: int = 0
    candidate_t: float = 0.0       # time of the last far reading taken as the candidate
    coast_t: float = 0.0           # time of the newest coasting prediction
    vspan: float = 0.0             # s: time span of the last chord in the velocity
    vfiltered: bool = True         # the velocity is low-passed (else a chord)
    turn: float = 0.0              # rad/s: rate of turn of the velocity's direction
    trail: list[tuple[float, float, float]] = dataclasses.field(default_factory=list)  # t, x, y
    steady: bool = False  # its turn was measured before its last return (3 readings or more)
    chord: tuple[float, float] = (0.0, 0.0)  # velocity estimate before any damping
    rival: Rival | None = None     # far readings of its id (tracking.rivals)
    decoy: tuple[float, float] | None = None  # a still place of its id that is not the puck


class PuckTracker:
    """Fuses observations into tracked pucks (see the module docstring).

    ``update(observations, t)`` takes the newest observation of every source (the same object
    again when a source has nothing new) and returns the pucks, sorted by id. ``step(measurements,
    t, source)`` does the same for bare measurements of one source (one camera frame).
    """

    def __init__(self, settings: TrackerSettings | None = None) -> None:
        self.s = settings or TrackerSettings()
        self.tracks: dict[int, _Track] = {}
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
        return {pid: self._predicted(tr, t) for pid, tr in tuple(self.tracks.items())}

    def reset(self) -> None:
        self.tracks.clear()
        self._seen_seq.clear()
        self._pucks = ()

    # ------------------------------------------------------------------ internals
    def _predicted(self, tr: _Track, t: float) -> tuple[float, float]:
        k = decayed_travel(1.0, t - tr.t, self.s.coast_decay_s)
        return tr.meas[0] + k * tr.chord[0], tr.meas[1] + k * tr.chord[1]

    def _gate(self, tr: _Track, t: float) -> float:
        u = self.s.units_per_metre
        return u * (self.s.gate_m + self.s.max_speed * max(t - tr.t, 0.0))

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
                self.tracks[pid] = self._new_track(best, source)
            elif not self._associate(tr, ms, source):
                self._miss(tr, ms[0].t)
        if complete:
            for pid, tr in self.tracks.items():
                if pid not in by_id and tr.source == source:
                    self._miss(tr, t)

    def _new_track(self, m: PuckMeasurement, source: str) -> _Track:
        meas = [float(m.x), float(m.y), float(m.angle)]
        tr = _Track(int(m.id), source, float(m.t), meas, list(meas), meas[:2], [0.0, 0.0],
                    meas[2:], [0.0])
        _take_measured_velocity(tr, m, self.s.max_speed * self.s.units_per_metre)
        tr.chord = (tr.vx, tr.vy)
        return tr

    def _associate(self, tr: _Track, ms: list[PuckMeasurement], source: str) -> bool:
        """Take the measurement consistent with the track; False if every one is an outlier."""
        t = ms[0].t
        if t < tr.t:
            return True  # older than what the track already holds (another source): ignore
        px, py = self._predicted(tr, t)
        gate, u = self._gate(tr, t), self.s.units_per_metre
        if len(ms) == 1 and tr.decoy is None:   # the usual case, without list overhead
            if math.hypot(ms[0].x - px, ms[0].y - py) <= gate:
                tr.candidate, tr.candidate_count = None, 0
                self._accept(tr, ms[0], source, relocated=False)
                return True
        dists = [math.hypot(m.x - px, m.y - py) for m in ms]
        if tr.decoy is not None:
            ms, dists = screened(ms, dists, tr.decoy, u * self.s.gate_m)
            if not ms:
                return False
        far = [i for i in range(len(ms)) if dists[i] > gate]
        if far:
            m = ms[min(far, key=lambda i: math.dist((ms[i].x, ms[i].y), (tr.rival.x, tr.rival.y))
                       if tr.rival else dists[i])]
            reach = u * (self.s.gate_m + self.s.max_speed * (t - tr.rival.t if tr.rival else 0.0))
            r = tr.rival = follow(tr.rival, m.x, m.y, t, reach, tr.meas, u * self.s.gate_m)
            if (r.moved() > u * self.s.gate_m and tr.state == "seen"
                    and math.hypot(tr.meas[0] - r.tx, tr.meas[1] - r.ty) <= u * self.s.gate_m):
                # The rival moves, the track's place lies still: the rival is the puck.
                # Rendered frames, puck and print of its marker lying still, the puck then
                # moved at 0.4 m/s: taken 0.15-0.2 s after it starts, then 5-11 mm off (held
                # by the print, 0.47-0.57 m); the bench's figures without prints unchanged.
                tr.decoy, tr.rival = (tr.meas[0], tr.meas[1]), None
                tr.candidate, tr.candidate_count = None, 0
                self._accept(tr, m, source, relocated=True)
                return True
        k = min(range(len(ms)), key=dists.__getitem__)
        if dists[k] <= gate:
            tr.candidate, tr.candidate_count = None, 0
            self._accept(tr, ms[k], source, relocated=False)
            return True
        # Far from the track: a false detection, unless it keeps appearing at the same place.
        m = ms[k]
        still_at, still_t = tr.candidate, tr.candidate_t
        tr.candidate_t = t
        if (tr.candidate is not None
                and math.hypot(m.x - tr.candidate[0], m.y - tr.candidate[1]) <= u * self.s.gate_m):
            tr.candidate_count += 1
        else:
            tr.candidate_count = 1
        tr.candidate = (m.x, m.y)
        if tr.candidate_count >= self.s.confirm_frames:
            tr.candidate, tr.candidate_count = None, 0
            if (math.hypot(*tr.chord) > STILL_SPEED * u and not tr.reacquiring
                    and still_at is not None and math.hypot(m.x - still_at[0], m.y - still_at[1])
                    <= STILL_SPEED * u * max(t - still_t, 0.0) + 1e-3 * u):
                # A still place read again and again while the track was moving: a print
                # of its marker, not the puck moved there. Rendered frames, a circling puck
                # hidden 0.3 s by a hand: 53-57 mm off while coasting (relocated to the print,
                # 0.47-0.63 m off until dropped).
                tr.decoy = (m.x, m.y)
                return False
            self._accept(tr, m, source, relocated=True)
            return True
        return False

    def _accept(self, tr: _Track, m: PuckMeasurement, source: str, relocated: bool) -> None:
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
        self._turned(tr, meas, t, returning or relocated, relocated)
        _take_measured_velocity(tr, m, s.max_speed * u)
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

    def _turned(self, tr: _Track, meas: list[float], t: float, broken: bool,
                relocated: bool) -> None:
        """Update the rate of turn of the puck's direction of travel (tracking.turning). A puck
        back from a coast keeps turning as it did; a relocated one does not. Reset at a return,
        pucks on 9 cm circles read in 7-8% of frames (12.8 mm blur) were shown worse: overall
        p95 181.7 -> 189.6 mm at 60 Hz, 180.0 -> 184.9 mm at 30 Hz, nine seeds pooled."""
        if broken:
            tr.steady = len(tr.trail) >= 3 and not relocated
            tr.trail = []
            if relocated:
                tr.turn = 0.0
        if tr.trail and t <= tr.trail[-1][0]:
            return  # another reading of the same moment
        tr.trail = extend_trail(tr.trail, t, meas[0], meas[1])
        if len(tr.trail) < 3:
            return
        sample = turn_sample(tr.trail, TURN_SPEED * self.s.units_per_metre)
        if sample is None:  # turned back, not turning
            tr.turn = 0.0
            return
        dt = max(t - tr.t, 1e-6)
        a = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * self.s.velocity_cutoff_hz * dt))
        tr.turn += a * (min(max(sample, -MAX_OMEGA), MAX_OMEGA) - tr.turn)

    def _miss(self, tr: _Track, t: float) -> None:
        # A reappeared puck's gap is held, not closed, while it is hidden again: closing it
        # then too made the shown pose of pucks seen in 14-17% of frames (motion blur) worse
        # (p95 198-257 -> 256-289 mm).
        if tr.state != "coasting":
            tr.state, tr.anchor = "coasting", list(tr.out)
        k = decayed_travel(1.0, t - tr.t, self.s.coast_decay_s)
        a = tr.anchor
        dx, dy = turned_travel(*self._led(tr), tr.turn, t - tr.t, self.s.coast_decay_s)
        tr.out = [a[0] + dx, a[1] + dy, a[2] + k * tr.omega]
        tr.coast_t = max(t, tr.t)

    def _led(self, tr: _Track) -> tuple[float, float]:
        """The held velocity turned to where the puck heads when it was last read."""
        return led_velocity(tr.vx, tr.vy, tr.turn, tr.vspan,
                            self.s.velocity_cutoff_hz if tr.vfiltered else None)

    def _expire(self, t: float) -> None:
        for tr in self.tracks.values():
            if tr.state == "seen" and t - tr.t > self.s.stale_s:
                self._miss(tr, t)  # its source went quiet: no longer seen
        for pid in [p for p, tr in self.tracks.items() if t - tr.t > self.s.coast_s]:
            del self.tracks[pid]

    def _puck(self, tr: _Track) -> Puck:
        k, vx, vy = 1.0, tr.vx, tr.vy
        if tr.state == "coasting":  # the velocity of the prediction shown: turned and faded
            dt = max(tr.coast_t - tr.t, 0.0)
            k = math.exp(-dt / self.s.coast_decay_s)
            vx, vy = turned_velocity(*self._led(tr), tr.turn, dt, self.s.coast_decay_s)
        return Puck(tr.id, tr.out[0], tr.out[1], wrap_angle(tr.out[2]), vx, vy,
                    tr.omega * k, tr.state,  # type: ignore[arg-type]
                    raw_x=tr.meas[0], raw_y=tr.meas[1], raw_angle=wrap_angle(tr.meas[2]))


def _take_measured_velocity(tr: _Track, m: PuckMeasurement, most_speed: float) -> None:
    """The velocity the source measured, where it measured one, replaces the estimate; held
    to ``most_speed`` (units/s) and MAX_OMEGA, so a sender's absurd figure cannot carry the
    prediction (the gate, the coasting) off the table."""
    if math.isfinite(m.vx) and math.isfinite(m.vy):
        vx, vy = float(m.vx), float(m.vy)
        speed = math.hypot(vx, vy)
        k = most_speed / speed if speed > most_speed else 1.0
        tr.vx, tr.vy = vx * k, vy * k
    if math.isfinite(m.omega):
        tr.omega = min(max(float(m.omega), -MAX_OMEGA), MAX_OMEGA)
