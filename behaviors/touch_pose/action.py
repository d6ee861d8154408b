"""Action control (paper 003, section 5): recognising a drag as an action, then its time control.

Executing condition. Each action's average primary-part trajectory (its stroke: generalised time
0 .. ``stroke_end``) is kept in 3-D relative to the character; per view it is projected onto the
screen from where the part stands now. A dragged trajectory (screen points and times since the
finger last rested, over at most twice the stroke's duration) is compared with it by dynamic
programming (equation 1):

    D = sum over matched pairs |p_in - p_act| + h |t_in - t_act|,  averaged over the pairs.

The DP steps the input one sample at a time and the action 0, 1 or 2 samples (so an input may
run up to twice as fast as the recording without leaving samples unmatched, and each row depends
only on the previous one: the whole table is a few vectorised numpy rows; steps of up to 3,
tried for drags three times the pace, started the punch at that speed (21 of 31 strokes at 3x
instead of 16) but drags turned away started an action 38 times in 589 instead of 33, so 2 is
kept). The action end is
open: every action prefix covering more than half the stroke (``MIN_COVERAGE``) is tried and the
best kept. The threshold loosens with the drag's speed (:func:`threshold`); an input shorter than
``MIN_LENGTH`` (half) of the projected stroke's length or ``MIN_SECONDS`` is not judged, so
"covers more than half the action trajectory" holds in space as well as along the DP path; nor
is one slower than ``MIN_RELATIVE_SPEED`` of the stroke's pace (it could not pass). An action
whose representative vector (stroke end minus start) is within 45 degrees of the viewing line
is excluded.

Parameters (measured over the actions' strokes (punch, kick, jump, spin kick, wave) dragged at 1,
1.5, 2, 3 and 4 times their recorded duration, from three views; character metres): ``H`` = 0.5 m
per second of time difference. The threshold loosens with the drag's speed relative to the stroke's
own projected speed r (absolute speeds differ too much between actions: a kick's foot moves ~6 m/s,
a wave's hand ~1.5 m/s): 0.05 m + 0.06 m x r. At the action's pace (r = 1) average distances of
0.004-0.01 m meet a threshold of 0.11 m, leaving room for an imprecise finger; at half pace the
kicks (0.05) still pass and the punch, jump and wave (0.09-0.11) do not; at a third of the pace or
slower (0.095-0.5) nothing does, so slow drags only pose.

A quick drag's threshold (up to 0.23 m at three times the pace) is at most a third of the
projected stroke's length (``MAX_THRESHOLD_OF_LENGTH``): the bow's stroke is only 0.35 m long
and the head dragged at right angles to it, quickly, started the bow. Measured with the engine
over the six actions from six views, each stroke dragged at 0.5-1.5 times its pace and turned
by 90, -90 and 180 degrees: accepted strokes' distances reach 0.32 of their stroke's length,
turned drags come no nearer than 0.37 for the bow (0.13 for the jump, which a quick sideways
drag of the pelvis still starts); with 0.34, drags turned away started their own action 5
times in 496 instead of 24 (the bow 0 instead of 19), and every stroke started as before
(121 of 124; 0.25 measured the same).

Which action a drag starts: the first, frame by frame, whose distance passes its threshold (of
those passing at once, the one furthest under it), as section 5 initiates an action once "D is
lower than a threshold", judged when the input "has certain length and S covers more than half
the action trajectory". A short stroke can thus be judged, and pass, on the opening of a longer
one of the same part before the longer one may be judged at all: the punch's stroke dragged at
its pace from 90,40 fitted the wave's (0.553 m on the screen there, 0.722 from 90,15; 48.5
degrees from the eye, 3.5 above the exclusion) at 0.1045 m, under its threshold (0.170 at that
speed, 0.11 even at the wave's pace), 0.167 s into the drag (0.299 m of the punch's 1.814 m),
and the wave started; the punch may be judged only at 0.984 m, where it fits at 0.0095 m
(threshold 0.104). So a match waits while a longer stroke of the same part, too short yet to
be judged, fits the drag's opening (any prefix) nearer than the match fits its own stroke:
the drag may be going on along it (the project's own addition; the paper leaves it to the view).
Measured over the seven actions' strokes dragged over 1 and 1.5 times their stroke's duration
from 36 views (every 30 degrees of azimuth, elevations 10, 25, 40; 138 of 504 drags excluded):
drags starting another action than their own 7 -> 1 (punch as wave from 90,25, 90,40 and
120,40, kick as spin kick from 210,25 at 1.5: all now start their own but the punch over 1.5
from 120,40, still the wave); strokes starting their own action 348 -> 354, none later by a
frame; none starting nothing 11 -> 11. The same strokes turned by 90, -90 and 180 degrees, over
0.5 and 1 times their duration (1098 drags), started the same actions as before.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from behaviors.touch_pose.humanoid import PARTS, Humanoid
from behaviors.touch_pose.latent import LearnedModel
from behaviors.touch_pose.samples import ActionSpec, Segment, clip_named, clip_poses, segment_at

H = 0.5
THRESHOLD_BASE = 0.05
THRESHOLD_PER_SPEED = 0.06
MIN_COVERAGE = 0.5
#: The threshold never exceeds this fraction of the projected stroke's length (see the docstring).
MAX_THRESHOLD_OF_LENGTH = 0.34
MIN_LENGTH = 0.5
MIN_SECONDS = 0.15
#: Drags slower than this fraction of the stroke's pace are not judged (none matched at 1/3).
MIN_RELATIVE_SPEED = 0.25
#: A finger slower than this fraction of a stroke's pace is resting: the drag starts after it.
STILL_FRACTION = 0.1
EXCLUDE_DEG = 45.0
ACTION_SAMPLES = 24
MAX_INPUT_SAMPLES = 64
WINDOW = 2.0
#: Fastest the generalised time moves, in multiples of the recording's own pace. The paper's
#: interval is one frame of the recording (1.0); measured with the six actions dragged at 0.5,
#: 0.75, 1 and 1.5 times their pace from three views, 1.0 followed the finger no better as a
#: whole (primary part's median distance from it, mean over cases: punch 0.047 -> 0.032 m,
#: but kick 0.034 -> 0.043 and jump 0.008 -> 0.015 m), so 1.6 is kept.
MAX_PACE = 1.6
#: The finger moves along an action (for the segments that forbid stillness) when its
#: synthesised time has gone more than ``FINGER_BAND`` (generalised time) one way from its lowest
#: or highest over the last ``FINGER_WINDOW`` s. Touches held still with 1-3 mm of uniform jitter
#: (kick, walk, spin kick, punch, jump, four seeds) span at most 0.036 within the window (the
#: walk's; the kick's 0.025), while a drag back at half the walk's or the kick's pace moves it
#: 0.08 or 0.065.
FINGER_WINDOW = 0.2
FINGER_BAND = 0.05
#: Where the action may stand, a finger resting (its synthesised time not moving by
#: ``FINGER_BAND`` over ``FINGER_WINDOW``, and the finger itself within ``REST_SPAN`` over
#: ``REST_WINDOW``: :mod:`behaviors.touch_pose.action_control`) holds that time low-passed at
#: ``REST_CUTOFF`` Hz while it stays within ``REST_BAND`` (generalised time) of it; beyond, or
#: moving, the time follows the synthesis itself. The hold is the project's own addition to
#: section 5 (it keeps the section's stillness). A resting finger's synthesised time flips between
#: neighbouring samples (a punch held with 1 mm of jitter, view 90,15: 0.810 <-> 0.831 frame
#: after frame). Measured (bench/touch_pose_rest.py: the action time's back-and-forth while a
#: finger with 1 mm of jitter rests, s, median / largest; the primary part's mean distance from
#: a finger dragging back along the stroke, wave to 0.3 and bow to 0.3, table m):
#:
#:                                   punch        wave        bow          back: wave  bow
#:     followed every flip            0.035/0.78   0.021/0.80  0.45/0.98    0.0243  0.0083
#:     this (0.1 Hz, 0.03)            0.0001/0.005 0/0.12      0.005/0.012  0.0243  0.0083
#:     held, no low-pass              0/0          0/0.11      0/0          0.0246  0.0100
#:     One Euro, 1 Hz, beta 0         0.0014/0.089 0.003/0.13  0.10/0.15    0.0327  0.0083
#:     One Euro, 0.5 Hz, beta 10 s    0.0029/0.11  0.001/0.14  0.12/0.20    0.0256  0.0084
#:
#: (One Euro: cutoff + beta x speed, speed low-passed at 1 Hz, in the still segments.) The flips
#: move the time 0.02 a frame, 0.6 per second, as fast as a real drag (the wave's pace is 0.42
#: per second), so no beta tells them apart: a beta low enough to hold a resting finger lags a
#: moving one. The finger's window does tell them apart, so the hold gives way to it. A finger
#: dragging back 3 or 5 times slower than the stroke moves the time less than the band, so the
#: time alone held it too (the wave's gap 0.0199 / 0.0181 m following every flip, 0.0208 /
#: 0.0196 held); with the finger's own span as a condition it is 0.0199 / 0.0181, and the rest
#: figures above become punch 0.0004/0.004, wave 0.0002/0.08, bow 0.004/0.010. Left: the wave
#: from 90,15 with 2 mm of jitter flips 0.06 (more than the band), 0.89 s at most.
REST_CUTOFF = 0.1
REST_BAND = 0.03


@dataclass
class ActionModel:
    """An action's spec, its learned model (all frames of its sample motions) and the average
    stroke of its primary part."""

    spec: ActionSpec
    duration: float
    model: LearnedModel
    stroke: np.ndarray        # (ACTION_SAMPLES, 3) primary part, relative to its start, model frame
    stroke_t: np.ndarray      # (ACTION_SAMPLES,) seconds from the start
    vector: np.ndarray        # representative direction (3,)
    start: float              # generalised time where the stroke starts

    @property
    def name(self) -> str:
        return self.spec.name

    def segment(self, u: float) -> Segment:
        return segment_at(self.spec, u)

    def projected(self, view: np.ndarray) -> tuple[np.ndarray, float]:
        """The stroke on the screen of ``view`` (2, 3) and its length (m); cached per view."""
        key = view.tobytes()
        cache = self.__dict__.setdefault("_projected", {})
        if key not in cache:
            if len(cache) > 16:
                cache.clear()
            stroke = self.stroke @ view.T
            cache[key] = (stroke, float(np.linalg.norm(np.diff(stroke, axis=0), axis=1).sum()))
        return cache[key]


def build_action(body: Humanoid, spec: ActionSpec) -> ActionModel:
    """The learned model (every frame of every sample motion, each in time order) and the
    average primary-part stroke of one action."""
    part = PARTS.index(spec.part)
    poses, times, motion, strokes, stroke_ts, starts, durations = [], [], [], [], [], [], []
    for m, name in enumerate(spec.motions):
        clip = clip_named(name)
        u = (clip.times - clip.times[0]) / clip.duration
        poses += clip_poses(body, clip, u)
        times.append(u)
        motion.append(np.full(len(u), m))
        # the stroke starts once the primary part has moved a tenth of its way (a drag is the
        # part moving: the clips' first still frames are left to posing)
        fine = np.linspace(0.0, spec.stroke_end, 4 * ACTION_SAMPLES)
        traj = np.array([body.parts(p)[part] for p in clip_poses(body, clip, fine)])
        moved = np.linalg.norm(traj - traj[0], axis=1)
        start = fine[int(np.argmax(moved > 0.1 * moved.max()))]
        us = np.linspace(start, spec.stroke_end, ACTION_SAMPLES)
        traj = np.array([body.parts(p)[part] for p in clip_poses(body, clip, us)])
        strokes.append(traj - traj[0])
        stroke_ts.append((us - start) * clip.duration)
        starts.append(start)
        durations.append(clip.duration)
    model = LearnedModel(body, poses, times=np.concatenate(times), motion=np.concatenate(motion))
    # the average trajectory (section 5): the motions' strokes sample by sample (the same
    # generalised-time steps from each one's start)
    stroke = np.mean(strokes, axis=0)
    return ActionModel(spec, float(np.mean(durations)), model, stroke, np.mean(stroke_ts, axis=0),
                       stroke[-1].copy(), float(np.mean(starts)))


def dp_distance(inp: np.ndarray, inp_t: np.ndarray, act: np.ndarray, act_t: np.ndarray,
                h: float = H, min_coverage: float = MIN_COVERAGE) -> tuple[float, int]:
    """(average equation-1 distance, last matched action index) of the best alignment of the
    whole input with an action prefix covering more than ``min_coverage``; (inf, -1) if none.

    ``inp`` (n, 2), ``act`` (m, 2): positions relative to their starts; times relative too.
    """
    n, m = len(inp), len(act)
    cost = (np.linalg.norm(inp[:, None, :] - act[None, :, :], axis=2)
            + h * np.abs(inp_t[:, None] - act_t[None, :]))
    big = np.inf
    d = np.full(m, big)
    d[0] = cost[0, 0]
    for i in range(1, n):
        prev = d
        best = prev.copy()
        best[1:] = np.minimum(best[1:], prev[:-1])
        best[2:] = np.minimum(best[2:], prev[:-2])
        d = cost[i] + best
    first = int(np.floor(min_coverage * (m - 1))) + 1
    if first >= m:
        return big, -1
    j = first + int(np.argmin(d[first:]))
    return float(d[j] / n), j


def threshold(relative_speed: float) -> float:
    """Largest accepted distance (m) for a drag at ``relative_speed`` times the stroke's speed."""
    return THRESHOLD_BASE + THRESHOLD_PER_SPEED * min(relative_speed, 3.0)


def resample(points: np.ndarray, times: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` samples evenly spaced in time of a trajectory (k, 2) at rising ``times``."""
    t = np.linspace(times[0], times[-1], n)
    return np.stack([np.interp(t, times, points[:, 0]), np.interp(t, times, points[:, 1])], 1), t


@dataclass
class Match:
    """A recognised action: its model, the distance, threshold and generalised start time."""

    action: ActionModel
    distance: float
    threshold: float
    start_u: float


def _since_rest(a: ActionModel, times: np.ndarray, step_speed: np.ndarray,
                view: np.ndarray) -> int | None:
    """Index of the drag's first point for ``a`` (since the finger last rested, within
    ``WINDOW`` strokes); None if too few points or too short a time follow it."""
    stroke_len = a.projected(view)[1]
    first = int(np.searchsorted(times, times[-1] - WINDOW * a.stroke_t[-1]))
    rested = np.flatnonzero(step_speed[first:] < STILL_FRACTION * stroke_len / a.stroke_t[-1])
    if rested.size:
        first += int(rested[-1]) + 1
    if len(times) - first < 3 or times[-1] - times[first] < MIN_SECONDS:
        return None
    return first


def _fit(a: ActionModel, screen_path: np.ndarray, times: np.ndarray, first: int,
         view: np.ndarray, min_coverage: float = MIN_COVERAGE) -> tuple[float, int]:
    """:func:`dp_distance` of the drag from ``first`` against ``a``'s stroke on the screen."""
    # the input at the action's own sample spacing: a drag as long as the stroke has as
    # many samples, a slower one more (matched one action sample each: DP step 0)
    w_rel = screen_path[first:] - screen_path[first]
    w_t = times[first:] - times[first]
    spacing = a.stroke_t[1] - a.stroke_t[0]
    n = int(min(max(4, round(w_t[-1] / spacing) + 1), MAX_INPUT_SAMPLES))
    inp, inp_t = resample(w_rel, w_t, n)
    return dp_distance(inp, inp_t, a.projected(view)[0], a.stroke_t, min_coverage=min_coverage)


def recognise(actions: list[ActionModel], part: str, screen_path: np.ndarray,
              times: np.ndarray, view: np.ndarray, excluded: set[str]) -> Match | None:
    """The best action whose primary part is ``part`` matching the dragged ``screen_path``
    (k, 2, character metres) at ``times`` (s); ``view`` maps relative 3-D to screen (2, 3).

    Per action, the input is the drag since the finger last rested (moved slower than
    ``STILL_FRACTION`` of the stroke's pace), over at most ``WINDOW`` times the stroke's
    duration: a visitor may hold a part, then strike. None while a longer stroke of the part,
    too long yet to be judged, fits the drag's opening better (see the module docstring)."""
    if len(times) < 3 or times[-1] - times[0] < MIN_SECONDS:
        return None
    steps = np.linalg.norm(np.diff(screen_path, axis=0), axis=1)
    step_speed = steps / np.maximum(np.diff(times), 1e-6)
    best: Match | None = None
    pending: list[tuple[ActionModel, int]] = []   # too short yet to be judged
    for a in actions:
        if a.spec.part != part or a.name in excluded:
            continue
        act_len = a.projected(view)[1]
        first = _since_rest(a, times, step_speed, view)
        if first is None:
            continue
        length = float(steps[first:].sum())
        relative = length / (times[-1] - times[first]) / max(act_len / a.stroke_t[-1], 1e-6)
        if length < MIN_LENGTH * act_len:
            pending.append((a, first))
            continue  # too short (no DP needed)
        if relative < MIN_RELATIVE_SPEED:
            continue  # so slow it is posing
        dist, j = _fit(a, screen_path, times, first, view)
        thr = min(threshold(relative), MAX_THRESHOLD_OF_LENGTH * act_len)
        if dist < thr and (best is None or dist - thr < best.distance - best.threshold):
            best = Match(a, dist, thr, a.start + float(a.stroke_t[j] / a.duration))
    if best is not None:
        own = best.action.projected(view)[1]
        for a, first in pending:
            if a.projected(view)[1] > own and \
                    _fit(a, screen_path, times, first, view, min_coverage=0.0)[0] < best.distance:
                return None   # the drag may be going on along the longer stroke
    return best


class ActionClock:
    """Generalised time of a running action (section 5, "posture synthesis during action control").

    While the finger touches, each frame the time moves toward the synthesised time by at most
    ``MAX_PACE`` times the recording's pace, forward or backward as the finger leads ("stopped or
    executed backward depending on the user's control"). Where the segment forbids stillness
    it never stands: it runs at least at the recording's pace in the way it last ran through
    such a segment (``heading``), turned only by a clear move of the finger the other way (its
    synthesised time going more than ``FINGER_BAND`` that way from its extreme over the last
    ``FINGER_WINDOW``, and lying that way).
    So a kick in the air held still runs on, one dragged back rewinds, and one dragged back and
    held goes on back out of the air. The time enters such a segment only the way it last ran
    or the way the finger clearly moves: a resting finger neither pulls a finished kick back into
    the air nor replays a rewound one. Where it may stand, a resting finger's synthesised time
    is held (``REST_CUTOFF``, ``REST_BAND``): its jitter flips it between neighbouring samples.
    Once the finger lifts it runs in the segment's automatic
    direction at the recording's pace. ``done`` once it reaches 1 (finished) or 0 (cancelled).
    """

    def __init__(self, action: ActionModel, u: float) -> None:
        self.action = action
        self.u = float(min(max(u, 0.0), 1.0))
        self.done = False
        self.heading = 1            # an action is recognised from a drag forward
        self._elapsed = 0.0
        self._recent: deque[tuple[float, float]] = deque()   # (s, synthesised time) in the window
        self._rest: float | None = None   # the resting finger's low-passed synthesised time
        #: whether this step's time came from a resting finger's held time (then action_control
        #: keeps the posture output when the hold took over: its REST_SPAN)
        self.held = False

    def finger(self, dt: float, target: float) -> tuple[float, float]:
        """How far the finger has gone forward and back along the action over the last
        ``FINGER_WINDOW`` s, given this frame's synthesised time ``target`` after ``dt`` s: the
        rise from the window's lowest synthesised time and the fall from its highest."""
        self._elapsed += dt
        recent = self._recent
        recent.append((self._elapsed, target))
        while recent[0][0] < self._elapsed - FINGER_WINDOW - 1e-9:
            recent.popleft()
        times = [u for _, u in recent]
        return target - min(times), max(times) - target

    def _resting(self, dt: float, target: float, resting: bool) -> float:
        """The synthesised time ``target`` a resting finger holds (see ``REST_CUTOFF``)."""
        self.held = resting and self._rest is not None and abs(target - self._rest) <= REST_BAND
        if not self.held:
            self._rest = target
        else:
            self._rest += (target - self._rest) * self.rest_weight(dt)
        return self._rest

    @staticmethod
    def rest_weight(dt: float) -> float:
        """The share (0-1) of a new value a low-pass at ``REST_CUTOFF`` Hz takes after ``dt`` s."""
        w = 2 * math.pi * REST_CUTOFF * dt
        return w / (1.0 + w)

    def step(self, dt: float, target: float | None, touching: bool, rests: bool = True) -> float:
        """Advance by ``dt`` s toward ``target`` (synthesised time, None without constraint);
        ``rests``: the finger itself stays put (the hold of ``REST_BAND`` may engage)."""
        pace = dt / self.action.duration
        seg = self.action.segment(self.u)
        if not touching or target is None:
            self.u += seg.direction * pace
            if not seg.still:
                self.heading = seg.direction
            self._recent.clear()
            self._rest = None
            self.held = False
        else:
            rise, fall = self.finger(dt, target)
            moves = {1: rise > FINGER_BAND, -1: fall > FINGER_BAND, 0: False}
            target = self._resting(dt, target,
                                   rests and seg.still and not (moves[1] or moves[-1]))
            step = float(np.clip(target - self.u, -MAX_PACE * pace, MAX_PACE * pace))
            if not seg.still:
                # no stillness here (a kick in the air): at least the recording's pace the way
                # it runs, faster when the finger leads further that way
                if np.sign(step) == -self.heading and moves[-self.heading]:
                    self.heading = -self.heading
                step = self.heading * max(pace, step * self.heading)
            new = self.u + step
            ahead = self.action.segment(min(max(new, 0.0), 1.0))
            if not ahead.still and new != self.u:
                if ahead is not seg and np.sign(step) != self.heading \
                        and not moves[int(np.sign(step))]:
                    new = self.u  # a resting finger does not pull the time into such a segment
                else:
                    self.heading = 1 if step > 0 else -1
            self.u = new
        if self.u >= 1.0 or self.u <= 0.0:
            self.u = min(max(self.u, 0.0), 1.0)
            self.done = True
        return self.u
