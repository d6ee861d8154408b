"""Action control (paper 003, section 5): recognising a drag as an action, then its time control.

Executing condition. Each action's average primary-part trajectory (its stroke: generalised time
0 .. ``stroke_end``) is kept in 3-D relative to the character; per view it is projected onto the
screen from where the part stands now. A dragged trajectory (screen points and times since the
finger went down) is compared with it by dynamic programming (equation 1):

    D = sum over matched pairs |p_in - p_act| + h |t_in - t_act|,  averaged over the pairs.

The DP steps the input one sample at a time and the action 0, 1 or 2 samples (so an input may
run up to twice as fast as the recording without leaving samples unmatched, and each row depends
only on the previous one: the whole table is a few vectorised numpy rows). The action end is
open: every action prefix covering more than half the stroke (``MIN_COVERAGE``) is tried and the
best kept. The threshold loosens with the drag's speed (:func:`threshold`); an input shorter than
``MIN_LENGTH`` of the stroke or ``MIN_SECONDS`` is not judged. An action whose representative
vector (stroke end minus start) is within 45 degrees of the viewing line is excluded.

Parameters (measured with the tests' drags, character metres): ``H`` = 0.15 m per second of time
difference, so a drag four times slower than the action scores about 0.15-0.3 m worse than one
at the action's own pace; threshold 0.06 m + 0.05 s x speed (m/s): a drag at the action's pace
(1.5-3 m/s for punch and kick) accepts average deviations of about 0.15-0.2 m, a slow posing
drag (0.3 m/s) only about 0.075 m, which its time term alone exceeds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from behaviors.touch_pose.humanoid import PARTS, Humanoid
from behaviors.touch_pose.latent import LearnedModel
from behaviors.touch_pose.samples import ActionSpec, Segment, clip_named, clip_poses, segment_at

H = 0.15
THRESHOLD_BASE = 0.06
THRESHOLD_PER_SPEED = 0.05
MIN_COVERAGE = 0.5
MIN_LENGTH = 0.3
MIN_SECONDS = 0.15
EXCLUDE_DEG = 45.0
ACTION_SAMPLES = 24
INPUT_SAMPLES = 16
#: Fastest the generalised time moves, in multiples of the recording's own pace.
MAX_PACE = 1.6


@dataclass
class ActionModel:
    """An action's spec, its learned model (all clip frames, in time order) and stroke."""

    spec: ActionSpec
    duration: float
    model: LearnedModel
    stroke: np.ndarray        # (ACTION_SAMPLES, 3) primary part, relative to its start, model frame
    stroke_t: np.ndarray      # (ACTION_SAMPLES,) seconds from the start
    vector: np.ndarray        # representative direction (3,)

    @property
    def name(self) -> str:
        return self.spec.name

    def segment(self, u: float) -> Segment:
        return segment_at(self.spec, u)


def build_action(body: Humanoid, spec: ActionSpec) -> ActionModel:
    """The learned model and average stroke of one action (one clip per action here)."""
    clip = clip_named(spec.clip)
    u = (clip.times - clip.times[0]) / clip.duration
    poses = clip_poses(body, clip, u)
    model = LearnedModel(body, poses, times=u)
    part = PARTS.index(spec.part)
    us = np.linspace(0.0, spec.stroke_end, ACTION_SAMPLES)
    traj = np.array([body.parts(p)[part] for p in clip_poses(body, clip, us)])
    stroke = traj - traj[0]
    return ActionModel(spec, clip.duration, model, stroke, us * clip.duration, stroke[-1].copy())


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


def threshold(speed: float) -> float:
    """Largest accepted distance (m) for a drag at ``speed`` (screen m/s, character scale)."""
    return THRESHOLD_BASE + THRESHOLD_PER_SPEED * speed


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


def recognise(actions: list[ActionModel], part: str, screen_path: np.ndarray,
              times: np.ndarray, view: np.ndarray, excluded: set[str]) -> Match | None:
    """The best action whose primary part is ``part`` matching the dragged ``screen_path``
    (k, 2, character metres) at ``times`` (s); ``view`` maps relative 3-D to screen (2, 3)."""
    if len(times) < 3 or times[-1] - times[0] < MIN_SECONDS:
        return None
    rel = screen_path - screen_path[0]
    length = float(np.linalg.norm(np.diff(screen_path, axis=0), axis=1).sum())
    duration = float(times[-1] - times[0])
    speed = length / duration
    best: Match | None = None
    inp, inp_t = resample(rel, times - times[0], INPUT_SAMPLES)
    for a in actions:
        if a.spec.part != part or a.name in excluded:
            continue
        stroke = a.stroke @ view.T
        act_len = float(np.linalg.norm(np.diff(stroke, axis=0), axis=1).sum())
        if length < MIN_LENGTH * act_len:
            continue
        dist, j = dp_distance(inp, inp_t, stroke, a.stroke_t)
        thr = threshold(speed)
        if dist < thr and (best is None or dist - thr < best.distance - best.threshold):
            best = Match(a, dist, thr, float(a.stroke_t[j] / a.duration))
    return best


class ActionClock:
    """Generalised time of a running action (section 5, "posture synthesis during action control").

    Each frame the time moves toward the synthesised time by at most ``MAX_PACE`` times the
    recording's pace; where the segment forbids stillness it keeps running in the segment's
    direction while the finger rests; once the finger lifts it runs in the segment's automatic
    direction at the recording's pace. ``done`` once it reaches 1 (finished) or 0 (cancelled).
    """

    def __init__(self, action: ActionModel, u: float) -> None:
        self.action = action
        self.u = float(min(max(u, 0.0), 1.0))
        self.done = False

    def step(self, dt: float, target: float | None, touching: bool) -> float:
        """Advance by ``dt`` s toward ``target`` (synthesised time, None without constraint)."""
        pace = dt / self.action.duration
        seg = self.action.segment(self.u)
        if not touching or target is None:
            self.u += seg.direction * pace
        else:
            delta = target - self.u
            step = float(np.clip(delta, -MAX_PACE * pace, MAX_PACE * pace))
            if not seg.still and abs(step) < pace:
                # no stillness here: keep going, the way the finger leads or the segment runs
                direction = np.sign(delta) if abs(delta) > 1e-6 else seg.direction
                step = direction * pace
            self.u += step
        if self.u >= 1.0 or self.u <= 0.0:
            self.u = min(max(self.u, 0.0), 1.0)
            self.done = True
        return self.u
