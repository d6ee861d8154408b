"""A tracked puck's state and the tracker's settings (see tracking.pucks).

Units: whatever the measurements use, table metres by default; ``units_per_metre`` converts the
metre-valued settings. Angles in radians, times in seconds.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from tabletop.frames import PuckMeasurement
from tracking.rivals import Rival

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
class Track:
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


def take_measured_velocity(tr: Track, m: PuckMeasurement, most_speed: float) -> None:
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


def new_track(m: PuckMeasurement, source: str, s: TrackerSettings) -> Track:
    """A track started at its first measurement ``m`` from ``source``."""
    meas = [float(m.x), float(m.y), float(m.angle)]
    tr = Track(int(m.id), source, float(m.t), meas, list(meas), meas[:2], [0.0, 0.0],
               meas[2:], [0.0])
    take_measured_velocity(tr, m, s.max_speed * s.units_per_metre)
    tr.chord = (tr.vx, tr.vy)
    return tr
