"""Features of a main/reactor pair (paper section 4.2), batch for training and per sample live.

Per entity and sample i (sampled at the generation rate, dt = 1/rate):

- velocity: |p_i - p_{i-1}| / dt, metres per second (0 at the first sample); per sample, the
  hands' tremor included. The velocity features from a causal average of the steps instead
  (exponential, 0.1 s / 0.04 s, live and in training alike): bench/fidelity.py --seeds
  0,1,2,3,4,5 664 -> 645 / 638 of 720 (the afraid character 24 -> 34 / 33 misses, every
  other character fewer met too);
- movement direction: atan2 of p_i - p_{i-1}; held from the previous sample while the entity
  moves slower than ``min_speed`` (a still puck's jitter has no direction), and equal to the
  look direction before the first movement;
- normalised look direction: look - movement direction (0 = looking where it goes, pi = backing);
- delta direction: change of movement direction from the previous sample;
- relative position (reactor only): the reactor's position in the main character's frame,
  ``fwd`` along the main's look direction and ``left`` to its left, metres;
- relative look direction: reactor look - main look;
- room (an extension, off unless Params.w_room > 0): the reactor's free room on its table along
  the bearing from its main (how far it can still back away) and to that bearing's left less
  its right, metres clipped at ROOM_CLIP (:func:`room`). The paper's features ignore the
  table; with the room the match can tell a moment with a wall behind the reactor from one in
  the open, and learn from the demonstration what the character does there. A live sample's
  room counts by how near its main is (:func:`room_gate`).

All angles are wrapped to (-pi, pi]. For the distance computations every angle is embedded as a
point on the unit circle (cos, sin): the squared distance between two embedded angles is
4 sin^2(d/2) for a difference d, which is d^2 for small d and correct across the wrap at pi.

Each feature is weighted by the inverse of its spread over the training data (standard deviation;
for an angle the root mean square distance of its embedding from their mean; for the relative
position, one spread for both axes, their root mean square, so the geometry stays isotropic)
with a floor per unit, so
no unit dominates and a nearly constant feature does not turn its noise into the whole cost.
The paper compares the raw feature vectors by squared Euclidean distance, in its own units
(pixels, radians); in metres a position differs by tenths where an angle's embedding differs by
ones, so unweighted the situation is mostly the relative look. Measured with
``bench/fidelity.py --seeds 0,1,2,3,4,5,8,9,10,11,12,13,26,27,28,29,30,31`` (thresholds met of
720 on seeds 0-5 / 8-13 / 26-31, the engine's alone in brackets): inverse spreads 676 / 671 /
661 (8 / 13 / 16); every scale 1 (the designer's weights alone) 673 / 673 / 664 (14 / 19 / 22),
the pursuit paths 137 -> 116 of 144.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from behaviors.puppet_master.table_boundary import table_reach
from tabletop.frames import wrap_angles

SITUATION_DIMS = 6   # v_main, v_react, fwd, left, cos/sin relative look (+ room: ROOM_DIMS)
COHERENCE_DIMS = 8   # cos/sin normalised look, cos/sin delta direction, fwd, left, v_react, v_main

SPEED_FLOOR = 0.02      # m/s
POSITION_FLOOR = 0.02   # m
ANGLE_FLOOR = 0.05      # rad
ROOM_DIMS = 2        # the reactor's room on the table: behind it, to its left less its right
ROOM_CLIP = 0.3         # m: the room beyond which a wall does not matter (features.room)
ROOM_NEAR = 0.5         # m: a live main this far or farther leaves the room out (room_gate)


@dataclass(frozen=True)
class PairFeatures:
    """Per-sample features of a pair; arrays of shape (n,). Units in the module docstring."""

    v_main: np.ndarray
    v_react: np.ndarray
    move_main: np.ndarray
    move_react: np.ndarray
    norm_look_main: np.ndarray
    norm_look_react: np.ndarray
    rel_fwd: np.ndarray
    rel_left: np.ndarray
    rel_look: np.ndarray
    ddir_main: np.ndarray
    ddir_react: np.ndarray


@dataclass(frozen=True)
class Scales:
    """Feature weights (1 / spread, times the designer's weight per feature)."""

    v_main: float
    v_react: float
    rel_position: float
    rel_look: float
    norm_look: float
    ddir: float
    room: float = 0.0
    still: float = 0.0
    since: float = 0.0


def movement(pos: np.ndarray, look: np.ndarray, rate_hz: float,
             min_speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Velocity (m/s), movement direction and delta direction (rad) of a path ``pos`` (n, 2)."""
    n = pos.shape[0]
    step = np.diff(pos, axis=0)
    speed = np.zeros(n)
    speed[1:] = np.hypot(step[:, 0], step[:, 1]) * rate_hz
    raw = np.empty(n)
    raw[0] = look[0]
    raw[1:] = np.arctan2(step[:, 1], step[:, 0])
    moving = speed >= min_speed
    moving[0] = True
    idx = np.maximum.accumulate(np.where(moving, np.arange(n), 0))
    move = raw[idx]
    ddir = np.zeros(n)
    ddir[1:] = wrap_angles(np.diff(move))
    return speed, move, ddir


def pair_features(main: np.ndarray, react: np.ndarray, rate_hz: float,
                  min_speed: float) -> PairFeatures:
    """Features of ``main`` and ``react`` poses, each (n, 3) of x, y, look direction."""
    vm, mm, ddm = movement(main[:, :2], main[:, 2], rate_hz, min_speed)
    vr, mr, ddr = movement(react[:, :2], react[:, 2], rate_hz, min_speed)
    dx = react[:, 0] - main[:, 0]
    dy = react[:, 1] - main[:, 1]
    c, s = np.cos(main[:, 2]), np.sin(main[:, 2])
    return PairFeatures(
        v_main=vm, v_react=vr, move_main=mm, move_react=mr,
        norm_look_main=wrap_angles(main[:, 2] - mm), norm_look_react=wrap_angles(react[:, 2] - mr),
        rel_fwd=c * dx + s * dy, rel_left=-s * dx + c * dy,
        rel_look=wrap_angles(react[:, 2] - main[:, 2]), ddir_main=ddm, ddir_react=ddr)


def angle_spread(a: np.ndarray) -> float:
    """Root mean square distance of the angles' unit-circle embedding from its mean."""
    r2 = float(np.mean(np.cos(a))) ** 2 + float(np.mean(np.sin(a))) ** 2
    return math.sqrt(max(0.0, 1.0 - r2))


def feature_scales(f: PairFeatures, w_velocity: float = 1.0, w_rel_position: float = 1.0,
                   w_rel_look: float = 1.0, w_norm_look: float = 1.0,
                   w_delta_direction: float = 1.0, w_room: float = 0.0) -> Scales:
    """Inverse-spread weights from training features, times the designer's weights (the
    room, metres as the relative position, by the relative position's spread)."""
    pos_spread = math.sqrt(0.5 * (float(np.var(f.rel_fwd)) + float(np.var(f.rel_left))))
    return Scales(
        v_main=w_velocity / max(float(np.std(f.v_main)), SPEED_FLOOR),
        v_react=w_velocity / max(float(np.std(f.v_react)), SPEED_FLOOR),
        rel_position=w_rel_position / max(pos_spread, POSITION_FLOOR),
        rel_look=w_rel_look / max(angle_spread(f.rel_look), ANGLE_FLOOR),
        norm_look=w_norm_look / max(angle_spread(f.norm_look_react), ANGLE_FLOOR),
        ddir=w_delta_direction / max(angle_spread(f.ddir_react), ANGLE_FLOOR),
        room=w_room / max(pos_spread, POSITION_FLOOR))


def _reach(px: np.ndarray, py: np.ndarray, ux: np.ndarray, uy: np.ndarray,
           table: tuple[float, float, float, float], clip: float) -> np.ndarray:
    """table_boundary.table_reach per sample, clipped to 0..clip (metres)."""
    x0, y0, x1, y1 = table
    with np.errstate(divide="ignore", invalid="ignore"):
        rx = np.where(ux > 0, (x1 - px) / ux, np.where(ux < 0, (x0 - px) / ux, np.inf))
        ry = np.where(uy > 0, (y1 - py) / uy, np.where(uy < 0, (y0 - py) / uy, np.inf))
    return np.clip(np.minimum(rx, ry), 0.0, clip)


def room(main: np.ndarray, react: np.ndarray, table: tuple[float, float, float, float],
         clip: float = ROOM_CLIP) -> np.ndarray:
    """(n, 2) the reactor's free room on the table (x0, y0, x1, y1), metres: along the bearing
    from its main (n, 2+) to it (n, 2+), how far it could still back away (0..clip); and to
    the bearing's left less to its right (-clip..clip), which way round it has room. ``clip``
    and 0 where the two are on one spot. As :func:`room_at` per sample."""
    dx, dy = react[:, 0] - main[:, 0], react[:, 1] - main[:, 1]
    rho = np.hypot(dx, dy)
    ok = rho > 1e-9
    r = np.where(ok, rho, 1.0)
    ux, uy = np.where(ok, dx / r, 1.0), np.where(ok, dy / r, 0.0)
    px, py = react[:, 0], react[:, 1]
    back = _reach(px, py, ux, uy, table, clip)
    side = _reach(px, py, -uy, ux, table, clip) - _reach(px, py, uy, -ux, table, clip)
    return np.column_stack([np.where(ok, back, clip), np.where(ok, side, 0.0)])


def room_at(mx: float, my: float, rx: float, ry: float,
            table: tuple[float, float, float, float],
            clip: float = ROOM_CLIP) -> tuple[float, float]:
    """The reactor's free room at (rx, ry) behind it and to the left less the right of the
    bearing from its main at (mx, my), metres (see :func:`room`)."""
    rho = math.hypot(rx - mx, ry - my)
    if rho <= 1e-9:
        return clip, 0.0
    ux, uy = (rx - mx) / rho, (ry - my) / rho
    back = max(0.0, min(table_reach(rx, ry, ux, uy, table), clip))
    left = max(0.0, min(table_reach(rx, ry, -uy, ux, table), clip))
    right = max(0.0, min(table_reach(rx, ry, uy, -ux, table), clip))
    return back, left - right


def main_still(main: np.ndarray, span: int, distance: float) -> np.ndarray:
    """(n,) 1.0 at the samples where the main (n, 2+ positions, metres) is within
    ``distance`` metres of where it was ``span`` - 1 samples before (of its first sample,
    sooner), else 0.0: its still/moving state as the live step reads it from its ring of the
    main's last ``span`` positions (causal; :func:`still_row`)."""
    i = np.arange(main.shape[0])
    j = np.maximum(i - span + 1, 0)
    return (np.hypot(main[i, 0] - main[j, 0], main[i, 1] - main[j, 1]) < distance
            ).astype(float)


STILL_FLOOR = 0.25      # the least spread of the main's still/moving state (a 0/1 flag)


def still_scale(still: np.ndarray) -> float:
    """The weight of the main's still/moving state (:func:`main_still`, 0/1) among the
    situation features: the inverse of its spread (standard deviation), as every feature,
    with a floor (STILL_FLOOR: the spread of a main standing in 1 of 15 samples; the shipped
    stalker's is 0.325), so a demonstration with few stops does not turn the flag into the
    whole cost; 0 (left out) where the demonstrated main never stood or never moved."""
    spread = float(np.std(still))
    return 1.0 / max(spread, STILL_FLOOR) if spread > 0.0 else 0.0


def since_push(distance: np.ndarray, touch: float, clip_steps: float) -> np.ndarray:
    """(n,) steps since the reactor last touched its main (``distance`` (n,) metres under
    ``touch``; 0 there and at the first sample, as the start counts as a push), at most
    ``clip_steps``: as :func:`since_step` advances it live, sample by sample, so the
    demonstration's samples and the live reactor's are counted alike.

    An extension of the paper's situation features, for a character that charges again and
    again (behavior.Behavior.charging: the bully) or circles its main and darts into it
    (Behavior.circling: the playful friend, figures in behavior.py). Its demonstrated designer lurks
    for a time after each push and then charges (every 2.8-4.6 s, 15 charges in its minute); the
    paper's features tell a moment just after a push from one about to charge only by where the
    reactor stands, and the match jumped between them every 2-3 steps, so the lurk lasted as
    long as the re-matching let it: beside slow mains the bully charged too often, beside fast
    ones too seldom (contact episodes on the 54 unseen paths of seeds 0-5, 8-13, 26-31, mean
    over 24 runs with the drift share x 1 + d, d = 0, +-0.001 ... +-0.012: slow 10.7-10.8,
    fast 9.7-9.9 against its designer's own character's 10.0 and 11.6 on the same paths; a
    path's count off the designer's by 1.3 / 2.4 / 1.5 on the slow / fast / loops paths).
    With the steps since the last push among the features the match takes moments as long
    after their push as the live reactor is after its own (10.3 / 10.5 episodes, off by 0.7-0.8
    / 1.6-1.7 / 1.2-1.3). See :func:`since_scale` for the weight and the figures."""
    out = np.zeros(distance.shape[0])
    k = 0.0
    for i in range(1, distance.shape[0]):
        k = since_step(k, float(distance[i]), touch, clip_steps)
        out[i] = k
    return out


def since_step(since: float, distance: float, touch: float, clip_steps: float) -> float:
    """The steps since the last push one step on: 0 where the reactor is nearer its main
    than ``touch`` metres, else one more, at most ``clip_steps``."""
    return 0.0 if distance < touch else min(since + 1.0, clip_steps)


def push_interval(distance: np.ndarray, touch: float) -> float:
    """The most steps the demonstrated reactor went without touching its main (``distance``
    (n,) metres under ``touch``) before touching it again, the start counting as a touch
    (0: it never touched): where :func:`since_push` stops counting, so a live reactor that
    has not pushed for longer matches the demonstration's longest waits (the bully 152
    steps, 3.8 s)."""
    since = since_push(distance, touch, math.inf)
    touched = np.flatnonzero(distance[1:] < touch)
    return float(since[touched].max()) if touched.size else 0.0


def since_scale(since: np.ndarray, weight: float) -> float:
    """The weight of the steps since the last push (:func:`since_push`) among the situation
    and coherence features: ``weight`` over their spread (standard deviation), as every
    feature; character.SINCE_WEIGHT 0.5, chosen on the data.

    The bully's misses (the engine's alone: where its designer's own character meets the
    threshold on the same path) over the 54 unseen paths of seeds 0-5, 8-13, 26-31, 24 runs
    (the drift share x 1 + d, d = 0, +-0.001 ... +-0.012), compiled step: without the
    feature 407 (332): contact 189, orbit 87, still/moving 131. In the situation and
    coherence vectors at weight 0.35 331 (230), 0.5 258 (161): contact 40, orbit 95,
    still/moving 123; 0.6 247 (158); 0.75 319 (221): orbit 160. In the situation vectors
    alone (the paper's similarity of the situation; coherence then continued moments
    whatever their time since a push) 0.5 289 (190), 0.75 307 (205); over the first 12 runs
    0.25 210 (153) (base 181 (142)), 1 174 (120), 2 251 (154): the heavier the weight, the
    fewer contact misses and the more orbit and still/moving ones (the relative position
    counts for less in the match). bench/fidelity.py --seeds 0-5 / 8-13 / 26-31: met 666 /
    661 / 660 -> 673 / 664 / 659 of 720, the engine's alone 13 / 19 / 22 -> 7 / 17 / 22; the
    bully's misses 7 (6) / 6 (4) / 6 (3) -> 0 / 3 (2) / 7 (3); the other characters and the
    pursuit identical (the feature is theirs only where their demonstration charges again
    and again, character.MIN_CHARGES)."""
    spread = float(np.std(since))
    return weight / spread if spread > 0.0 else 0.0


def since_column(s: Scales, first: int = SITUATION_DIMS) -> int:
    """The column of the steps since the last push in the situation vectors (``first``
    SITUATION_DIMS) or the coherence vectors (COHERENCE_DIMS): after the paper's features
    and the main's still/moving state where the scales weigh it."""
    return first + (1 if s.still > 0.0 else 0)


def room_column(s: Scales) -> int:
    """The first situation column of the room (after the paper's six, the main's
    still/moving state and the steps since the last push where the scales weigh them)."""
    return since_column(s) + (1 if s.since > 0.0 else 0)


def situation_vectors(f: PairFeatures, s: Scales, room_m: np.ndarray | None = None,
                      still: np.ndarray | None = None,
                      since: np.ndarray | None = None) -> np.ndarray:
    """(n, 6) situation-similarity vectors (4.3.1): velocities, relative position and look;
    then the main's still/moving state (``still`` (n,) 0/1, :func:`main_still`) where the
    scales weigh it (s.still > 0); then the steps since the last push (``since`` (n,),
    :func:`since_push`) where the scales weigh them (s.since > 0); then the reactor's room on
    the table (``room_m`` (n, 2) metres, :func:`room`) where the scales weigh it (s.room > 0;
    Params.w_room).

    The main's turn (the signed turn of its walking direction over two 0.25 s spans, 0 below
    0.05 m/s) as one more column for the stalker (Behavior.keeps_pace), weighed 0.5 / 1 / 2
    over its spread, Python step, the stalker's misses (the engine's) on seeds 0-5, 8-13,
    26-31 against 26 (17): 32 (22) / 34 (23) / 32 (24); at 1 its loops orbit 0.558 -> 0.569
    rad/s mean (its designer 0.647), its slow-path contact missed on 7 of 18 paths. Not used.
    For the chased afraid character, the main's step towards the reactor as one more column
    and the reactor speed's and the still state's weights: chased.py (none kept).
    The reactor's signed tangential speed round its main (the sense of its circling), or its
    velocity in the main's frame instead of its speed: figures in similarity.py. Not used. Nor
    for the stalker's orbit beside a turning main (its loops main walks faster than the shown
    one turned, so the velocities pick straight walks): the velocity and position weights, the
    main's delta direction, the reactor's angular rate round its main (similarity.py)."""
    cols = [s.v_main * f.v_main, s.v_react * f.v_react,
            s.rel_position * f.rel_fwd, s.rel_position * f.rel_left,
            s.rel_look * np.cos(f.rel_look), s.rel_look * np.sin(f.rel_look)]
    if s.still > 0.0 and still is not None:
        cols.append(s.still * still)
    if s.since > 0.0 and since is not None:
        cols.append(s.since * since)
    if s.room > 0.0 and room_m is not None:
        cols.extend([s.room * room_m[:, 0], s.room * room_m[:, 1]])
    return np.column_stack(cols)


def coherence_vectors(f: PairFeatures, s: Scales, still: np.ndarray | None = None,
                      since: np.ndarray | None = None) -> np.ndarray:
    """(n, 8) coherence vectors (4.3.2) of the reactor: normalised look, delta direction,
    relative position, velocity; and the main's velocity (the paper computes velocity on both
    entities); then the main's still/moving state and the steps since the last push where the
    scales weigh them (as :func:`situation_vectors`). Without the main's velocity a coherence
    match continues a stretch where the demonstrated main moved while the live main stands
    still: a stalker kept walking (measured on the slow path with pauses: 40% of steps with a
    still main chose coherence; targets moved at 0.14 m/s against 0.08 m/s in the
    demonstration's own still moments)."""
    cols = [s.norm_look * np.cos(f.norm_look_react), s.norm_look * np.sin(f.norm_look_react),
            s.ddir * np.cos(f.ddir_react), s.ddir * np.sin(f.ddir_react),
            s.rel_position * f.rel_fwd, s.rel_position * f.rel_left,
            s.v_react * f.v_react, s.v_main * f.v_main]
    if s.still > 0.0 and still is not None:
        cols.append(s.still * still)
    if s.since > 0.0 and since is not None:
        cols.append(s.since * since)
    return np.column_stack(cols)


class EntityMotion:
    """Live velocity / movement direction / delta direction of one entity, one sample a step."""

    __slots__ = ("x", "y", "move", "rate_hz", "min_speed")

    def __init__(self, x: float, y: float, look: float, rate_hz: float, min_speed: float) -> None:
        self.x, self.y, self.move = x, y, look
        self.rate_hz = rate_hz
        self.min_speed = min_speed

    def step(self, x: float, y: float) -> tuple[float, float, float]:
        """Advance to (x, y); returns (velocity m/s, movement direction, delta direction)."""
        dx, dy = x - self.x, y - self.y
        self.x, self.y = x, y
        speed = math.hypot(dx, dy) * self.rate_hz
        prev = self.move
        if speed >= self.min_speed:
            self.move = math.atan2(dy, dx)
        d = math.remainder(self.move - prev, math.tau)
        return speed, self.move, (math.pi if d == -math.pi else d)


def relative_pose(mx: float, my: float, md: float, rx: float, ry: float,
                  rd: float) -> tuple[float, float, float]:
    """Reactor pose in the main's frame: (fwd m, left m, relative look rad)."""
    c, s = math.cos(md), math.sin(md)
    dx, dy = rx - mx, ry - my
    d = math.remainder(rd - md, math.tau)
    return c * dx + s * dy, -s * dx + c * dy, (math.pi if d == -math.pi else d)


def situation_row(out: np.ndarray, s: Scales, v_main: float, v_react: float, fwd: float,
                  left: float, rel_look: float) -> None:
    """Write one live situation vector's paper part into ``out[:6]``, as
    :func:`situation_vectors` (the room, where the vectors carry it: :func:`room_row`)."""
    out[0] = s.v_main * v_main
    out[1] = s.v_react * v_react
    out[2] = s.rel_position * fwd
    out[3] = s.rel_position * left
    out[4] = s.rel_look * math.cos(rel_look)
    out[5] = s.rel_look * math.sin(rel_look)


def still_row(out: np.ndarray, s: Scales, still: bool, column: int) -> None:
    """Write the main's still/moving state (``still``: within the still distance of where it
    was at the oldest of its last positions, :func:`main_still`) into ``out[column]`` (the
    situation vector's SITUATION_DIMS, the coherence vector's COHERENCE_DIMS) where the
    vectors carry it (s.still > 0)."""
    if s.still > 0.0:
        out[column] = s.still if still else 0.0


def since_row(out: np.ndarray, s: Scales, since: float, column: int) -> None:
    """Write the steps since the last push (:func:`since_step`) into ``out[column]`` where
    the vectors carry them (s.since > 0)."""
    if s.since > 0.0:
        out[column] = s.since * since


def room_row(out: np.ndarray, s: Scales, mx: float, my: float, rx: float, ry: float,
             table: tuple[float, float, float, float]) -> None:
    """Write the reactor's room on the live ``table`` (:func:`room_at`, main at (mx, my),
    reactor at (rx, ry), metres) into its two columns (:func:`room_column`) where the
    situation vectors carry it (Params.w_room > 0); with the room off nothing is computed."""
    at = room_column(s)
    if out.shape[0] > at:
        back, side = room_at(mx, my, rx, ry, table)
        out[at] = s.room * back
        out[at + 1] = s.room * side


def room_gate(x: np.ndarray, s: Scales) -> float:
    """The weight (0..1) of a live situation vector ``x``'s room in its window distance:
    1 - (distance to the main) / ROOM_NEAR, at least 0 (the distance read from x's relative
    position, weighed by ``s``). A wall matters to a fleeing character whose main is near;
    with its main far it behaves as in the open, and the match then takes any moment of the
    demonstration, wall or none (similarity.SituationSearch's gate; the demonstration's
    vectors are not gated). ROOM_NEAR 0.5 m is the afraid designer's alarm distance
    (chased.ALARM_M); at 0.4 m (w_room 2) the afraid character's open-path misses rose to
    36.8 / 4.0 / 39.2 (figures as in Params.w_room's docstring; 0.5 m: 22.8 / 4.6 / 31.0)."""
    return max(0.0, 1.0 - math.hypot(x[2], x[3]) / (s.rel_position * ROOM_NEAR))


def coherence_row(out: np.ndarray, s: Scales, norm_look: float, ddir: float, fwd: float,
                  left: float, v_react: float, v_main: float) -> None:
    """Write one live coherence vector into ``out`` (8,), as :func:`coherence_vectors`."""
    out[0] = s.norm_look * math.cos(norm_look)
    out[1] = s.norm_look * math.sin(norm_look)
    out[2] = s.ddir * math.cos(ddir)
    out[3] = s.ddir * math.sin(ddir)
    out[4] = s.rel_position * fwd
    out[5] = s.rel_position * left
    out[6] = s.v_react * v_react
    out[7] = s.v_main * v_main
