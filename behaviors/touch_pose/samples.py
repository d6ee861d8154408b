"""Sample motions of touch-pose control (paper 003, sections 4-5): actions and posing postures.

Actions come from the DeepMimic humanoid clips of the ``pybullet`` wheel (punch, kick, jump, spin
kick, walk) plus a wave and a bow made here by hand (no DeepMimic clip waves or bows). Each action
names its primary body part, the generalised time where its characteristic stroke ends (the part of
the primary-part trajectory that a drag is matched against), and its time segments (section 5,
figure 5): from a generalised time on, whether stillness is allowed while the finger rests, and the
automatic direction once the finger lifts (+1 forward, -1 backward). The segments were set by hand
from the clips' primary-part trajectories (as the paper does), e.g. the kick may pause while the leg
is chambered low but not once the foot leaves the floor.

Sample motions per action (the paper uses one to four and averages the primary part's
trajectory over them). The wheel holds one recording of each action, each a single instance
(one punch, one kick, one jump, one spin kick: measured by the primary part's speed peaks), and no
second take. A mirrored clip is a real motion, but it is the same action in the paper's sense only
when its primary part stays the same: the jump's primary part, the pelvis, lies on the body's
midline, so the mirrored jump (the recorded jump with the other side leading; its pelvis drifts
0.06 m the other way) is a second sample of the jump and the jump's trajectory is the average of
both. Mirroring the punch, kick or spin kick would move their primary part to the left hand or
foot: another action (the paper's "right-hand punching action" has the right hand as primary
part), not a sample of this one, so they keep their one motion. The hand-made wave and bow stay
single too: the bow is left-right symmetric (its mirror adds nothing) and more hand-made takes of
the wave would be invented data, not samples. Nothing is time-warped or noised into a "sample".

The walk is one cycle of the walk clip (1.27 s, 1.24 m: the left foot steps, then the right),
the seam between its recorded half cycles mended (:func:`mend_seam`).
Its primary part is the left foot, whose step (generalised time 0.1-0.45) is a flat 1.2 m sweep
forward, told apart from the side and from above; no other action has that part, so no kick or
spin kick drag competes with it. Measured over six views, strokes dragged at 0.5-1.5 times
their pace: the walk's started it 24 times in 24; the other six actions' started theirs 121
times in 124 as before, and none started the walk; their drags turned 90, -90 or 180 degrees
started an action 33 times in 589 as before; the walk's turned drags started nothing (0 of
114). Once the foot has left the floor it cannot stop (a walking human finishes the step): from
0.1 on the walk runs on to the cycle's end while the finger rests or lifts; only a drag back
takes it back. It travels like the
punch: from the action's base, brought back within ``ROAM`` as it ends, kept on the table.

Posing samples: the standing pose, hand-made idle variations of it (weight shifts, arms a
little out) and the first part of every sample motion of every action (the paper's choice: the start
of an action is done by posing before the action is recognised), plus the walk cycle and the two
dances for the legs' and arms' range (the walk being an action too, its whole cycle stands for its
prefix: the posing model is the same as without the walk action).

Posing samples are taken in place (pelvis height and tilt kept, travel and heading removed), so
posing never walks the character away and touched parts stay under their fingers: section 4's
pelvis position and heading relative to the motion's initial state, even bounded to 0.15 m and
30 degrees, left a hand up to 0.1 m from its finger where IK cannot move the pelvis
(bench/touch_pose_posing.py holds the study).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from behaviors.motion.clips import (Clip, quat_from_axis_angle, quat_from_rotvec, quat_mul,
                                    quat_slerp)
from behaviors.motion.deepmimic import load_motion
from behaviors.touch_pose.humanoid import Humanoid, Pose, yaw_of
from behaviors.touch_pose.tracking import rot_diff


@dataclass(frozen=True)
class Segment:
    """From generalised time ``start`` on: may the character stay still, and where it runs alone."""

    start: float
    still: bool
    direction: int


@dataclass(frozen=True)
class ActionSpec:
    """An action: its clip (DeepMimic name or ``"wave"``), primary part, stroke end, segments,
    and further sample motions of the same action (clip names, see :func:`clip_named`)."""

    name: str
    clip: str
    part: str
    stroke_end: float
    segments: tuple[Segment, ...]
    more: tuple[str, ...] = ()

    @property
    def motions(self) -> tuple[str, ...]:
        """Every sample motion's clip name, the main clip first."""
        return (self.clip,) + self.more


#: Suffix of a clip name meaning that clip mirrored left for right (:func:`mirror_clip`).
MIRRORED = "/mirrored"

ACTIONS: tuple[ActionSpec, ...] = (
    ActionSpec("punch", "punch", "right_hand", 0.45,
               (Segment(0.0, True, -1), Segment(0.3, False, 1), Segment(0.75, True, 1))),
    ActionSpec("kick", "kick", "right_foot", 0.5,
               (Segment(0.0, True, -1), Segment(0.3, False, 1), Segment(0.8, True, 1))),
    ActionSpec("jump", "jump", "pelvis", 0.6,
               (Segment(0.0, True, -1), Segment(0.4, False, 1), Segment(0.85, True, 1)),
               more=("jump" + MIRRORED,)),
    ActionSpec("spinkick", "spinkick", "right_foot", 0.65,
               (Segment(0.0, True, -1), Segment(0.2, False, 1), Segment(0.9, True, 1))),
    ActionSpec("wave", "wave", "right_hand", 0.3,
               (Segment(0.0, True, -1), Segment(0.25, True, 1))),
    ActionSpec("bow", "bow", "head", 0.4,
               (Segment(0.0, True, -1), Segment(0.4, True, 1))),
    ActionSpec("walk", "walk", "left_foot", 0.45,
               (Segment(0.0, True, -1), Segment(0.1, False, 1))),
)

#: Generalised time up to which each action's frames join the posing samples.
POSING_PREFIX = 0.25


def segment_at(spec: ActionSpec, u: float) -> Segment:
    """The segment holding generalised time ``u``."""
    out = spec.segments[0]
    for s in spec.segments:
        if u >= s.start:
            out = s
    return out


def _hand_made(base: Clip, seconds: float, rise: float,
               fall: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The start of a hand-made clip of ``seconds`` at 30 fps: its times (s), their share of
    the clip (0..1), its values (every frame ``base``'s first, a standing pose) and a ramp
    eased (half a cosine) from 0 up to 1 over the first ``rise`` of the clip and back down
    over the last ``fall``."""
    n = int(round(seconds * 30)) + 1
    t = np.linspace(0.0, seconds, n)
    u = t / seconds
    values = np.repeat(base.values[:1], n, axis=0)
    ramp = np.clip(np.minimum(u / rise, (1.0 - u) / fall), 0.0, 1.0)
    return t, u, values, 0.5 - 0.5 * np.cos(math.pi * ramp)


def wave_clip(base: Clip, seconds: float = 2.4, waves: int = 3) -> Clip:
    """A hand-made wave: the right arm rises to the side, the forearm swings ``waves`` times, the
    arm comes down. Every other channel holds ``base``'s first frame (a standing pose)."""
    t, u, values, raise_ = _hand_made(base, seconds, 0.25, 0.2)
    swing = np.sin(2 * math.pi * waves * np.clip((u - 0.25) / 0.55, 0.0, 1.0))
    # the raised arm: abducted about the forward axis (towards the right, +z), turned forward a bit
    up = quat_mul(quat_from_axis_angle((0, 1, 0), -0.35), quat_from_axis_angle((1, 0, 0), -2.4))
    rest_q = base.values[0, base.slices["right_shoulder"]]
    rest_e = float(base.values[0, base.slices["right_elbow"]][0])
    for k in range(len(t)):
        values[k, base.slices["right_shoulder"]] = quat_slerp(rest_q, up, raise_[k])
        values[k, base.slices["right_elbow"]] = ((1 - raise_[k]) * rest_e
                                                 + raise_[k] * (1.2 + 0.5 * swing[k]))
    return Clip("wave", base.channels, t, values)


def bow_clip(base: Clip, seconds: float = 2.4) -> Clip:
    """A hand-made bow: the chest and neck bend forward (about 55 and 25 degrees), the bow is
    held a moment, the body straightens; the arms hang with the chest. Every other channel holds
    ``base``'s first frame."""
    t, _, values, down = _hand_made(base, seconds, 0.4, 0.35)
    forward = (0.0, 0.0, 1.0)  # about the character's right: negative angles lean forward
    chest0, neck0 = base.values[0, base.slices["chest"]], base.values[0, base.slices["neck"]]
    for k in range(len(t)):
        values[k, base.slices["chest"]] = quat_mul(quat_from_axis_angle(forward, -0.95 * down[k]),
                                                   chest0)
        values[k, base.slices["neck"]] = quat_mul(quat_from_axis_angle(forward, -0.45 * down[k]),
                                                  neck0)
    return Clip("bow", base.channels, t, values)


def mirror_clip(clip: Clip) -> Clip:
    """``clip`` mirrored through the vertical x-y plane (the humanoid's sagittal plane at rest):
    left and right joints swap, positions' z and rotations' x and y components change sign
    (a reflected rotation turns about the reflected axis, negated as an axial vector); the
    humanoid's left and right bodies are mirror images (offsets' z opposite, hinges about z),
    so the result is the same motion done with the other side leading."""
    values = clip.values.copy()
    sl = clip.slices
    values[:, sl["root_z"]] *= -1.0
    for name, channel in sl.items():
        if name.startswith("left_"):
            other = sl["right_" + name[5:]]
            values[:, channel], values[:, other] = clip.values[:, other], clip.values[:, channel]
    for c in clip.channels:
        if c.type == "quat":  # (w, x, y, z)
            values[:, sl[c.name].start + 1: sl[c.name].start + 3] *= -1.0
    return Clip(clip.name + MIRRORED, clip.channels, clip.times.copy(), values, loop=clip.loop)


#: Frames on each side of a recording's seam over which its jump is spread (:func:`mend_seam`).
SEAM_FRAMES = 6
#: A frame step counts as a seam when its largest joint turn is this many times the clip's
#: median largest turn per frame (the walk's seam: 28.8 degrees against a median of 4.3).
SEAM_FACTOR = 4.0


def mend_seam(clip: Clip) -> Clip:
    """``clip`` with its seam mended: the DeepMimic walk is two half cycles joined at frames
    18-19, where every joint jumps at once (left shoulder 28.8 degrees in one 1/30 s frame,
    right shoulder 13.1, left hip 10.0, root 7.2; elsewhere at most 6.7 and 4.3 typical), which
    the walk action played as popping. The step beyond the motion's own pace there (the
    average of the steps either side) is spread over :data:`SEAM_FRAMES` frames each side, half
    before and half after, tapering linearly: each channel's path is kept, the jump gone. Largest
    joint turn between the walk's samples 28.8 -> 12.2 degrees (right knee, the motion's own); per
    target frame while the walk is dragged, worst of four views (bench/touch_pose_turns.py
    ``walk_drag_deg``) 28.6 -> 20.5, in line with the wave's 21.0 and the jump's 26.1 (punch,
    kick and spin kick strike at 70-100); once the finger lifts 12.1 -> 13.0 (from most views
    the seam is passed while dragging). A clip whose largest step is within
    :data:`SEAM_FACTOR` of its median step has no seam and is returned as it is."""
    v, sl = clip.values, clip.slices
    n = len(v)
    # each channel's per-frame steps: rotation vectors for joints, differences otherwise
    steps = {c.name: rot_diff(v[1:, sl[c.name]], v[:-1, sl[c.name]]) if c.type == "quat"
             else np.diff(v[:, sl[c.name]], axis=0) for c in clip.channels}
    turn = np.zeros(n - 1)
    for c in clip.channels:
        if c.type == "quat":
            turn = np.maximum(turn, np.linalg.norm(steps[c.name], axis=1))
    s = int(np.argmax(turn))
    if n < 4 or s < 1 or s + 2 >= n or turn[s] < SEAM_FACTOR * float(np.median(turn)):
        return clip
    out = v.copy()
    k = np.arange(n)
    # share of the jump moved onto each frame: +1/2 .. 0 before the seam, -1/2 .. 0 after
    share = np.where(k <= s, 0.5 * np.clip(1 - (s - k) / SEAM_FRAMES, 0, 1),
                     -0.5 * np.clip(1 - (k - s - 1) / SEAM_FRAMES, 0, 1))
    for c in clip.channels:
        cols, step = sl[c.name], steps[c.name]
        jump = step[s] - 0.5 * (step[s - 1] + step[s + 1])
        if c.type == "quat":
            out[:, cols] = quat_mul(quat_from_rotvec(share[:, None] * jump), v[:, cols])
        else:
            out[:, cols] = v[:, cols] + share[:, None] * jump
    return Clip(clip.name, clip.channels, clip.times.copy(), out, loop=clip.loop)


@lru_cache(maxsize=None)
def clip_named(name: str) -> Clip:
    """A DeepMimic clip by short name, or the hand-made wave or bow; ``name`` + :data:`MIRRORED`
    is that clip mirrored."""
    if name.endswith(MIRRORED):
        return mirror_clip(clip_named(name[: -len(MIRRORED)]))
    if name == "wave":
        return wave_clip(load_motion("jump"))
    if name == "bow":
        return bow_clip(load_motion("jump"))
    if name == "walk":
        return mend_seam(load_motion(name))
    return load_motion(name)


def yaw_quat(yaw: float) -> np.ndarray:
    """The quaternion turning ``yaw`` radians about the vertical (model y)."""
    return quat_from_axis_angle((0.0, 1.0, 0.0), yaw)


def relative(pose: Pose, origin: Pose, in_place: bool = False) -> Pose:
    """``pose`` relative to the initial state ``origin``: horizontal position and heading measured
    from it (section 4: the relative position and orientation taken from the initial state)."""
    yaw0 = yaw_of(origin.rots[0])
    inv = yaw_quat(-yaw0)
    out = pose.copy()
    out.rots[0] = quat_mul(inv, pose.rots[0])
    if in_place:
        out.rots[0] = quat_mul(yaw_quat(-yaw_of(out.rots[0])), out.rots[0])
        out.root = np.array([0.0, pose.root[1], 0.0])
        return out
    d = pose.root - origin.root
    c, s = math.cos(-yaw0), math.sin(-yaw0)
    out.root = np.array([c * d[0] + s * d[2], pose.root[1], -s * d[0] + c * d[2]])
    return out


def place(rel: Pose, base_xz: np.ndarray, base_yaw: float) -> Pose:
    """A relative pose put on the character's base position (x, z) and heading (radians)."""
    out = rel.copy()
    out.rots[0] = quat_mul(yaw_quat(base_yaw), rel.rots[0])
    c, s = math.cos(base_yaw), math.sin(base_yaw)
    x, z = rel.root[0], rel.root[2]
    out.root = np.array([base_xz[0] + c * x + s * z, rel.root[1], base_xz[1] - s * x + c * z])
    return out


def clip_poses(body: Humanoid, clip: Clip, u: np.ndarray, in_place: bool = False) -> list[Pose]:
    """Poses of ``clip`` at generalised times ``u``, relative to its first frame."""
    origin = body.pose_from_values(clip, clip.sample(0.0))
    return [relative(body.pose_from_values(clip, v), origin, in_place) for v in clip.sample_many(u)]


def standing_pose(body: Humanoid) -> Pose:
    """The standing pose: the jump clip's first frame (arms relaxed), in place. It leans: the
    head is 21 degrees ahead of the pelvis. The backflip's first frame (6 degrees) was tried as
    the stand and the wave's and bow's rest: over 120 drags of a hand, foot or head to where
    other clips hold it (four views), the part ended 0.020 m from its goal on average (p90
    0.062, character metres) against 0.015 (0.054) with this one, so this one is kept."""
    return clip_poses(body, clip_named("jump"), np.array([0.0]), in_place=True)[0]


def idle_poses(body: Humanoid, stand: Pose) -> list[Pose]:
    """Hand-made idle variations of ``stand``: arms a little out or forward, head turned."""
    out = []
    names = body.names
    for side, sign in (("right", 1.0), ("left", -1.0)):
        for ax, ang in (((1, 0, 0), -0.5 * sign), ((0, 0, 1), 0.6), ((0, 0, 1), -0.4)):
            p = stand.copy()
            i = names.index(f"{side}_shoulder")
            p.rots[i] = quat_mul(quat_from_axis_angle(ax, ang), p.rots[i])
            out.append(p)
    for yaw in (-0.5, 0.5):
        p = stand.copy()
        i = names.index("neck")
        p.rots[i] = quat_mul(quat_from_axis_angle((0, 1, 0), yaw), p.rots[i])
        out.append(p)
    return out


def posing_samples(body: Humanoid, in_place: bool = True) -> list[Pose]:
    """The posing model's sample postures (about 140): in place, or with ``in_place`` False their
    pelvis position and heading relative to their motion's initial state."""
    stand = standing_pose(body)
    poses = [stand] + idle_poses(body, stand)
    whole = ("walk", "dance_a", "dance_b")
    for clip in (clip_named(m) for spec in ACTIONS for m in spec.motions if m not in whole):
        k = max(3, int(round(POSING_PREFIX * clip.duration * 15)))
        poses += clip_poses(body, clip, np.linspace(0.0, POSING_PREFIX, k), in_place)
    for name, step in zip(whole, (2, 4, 4)):
        clip = clip_named(name)
        n = len(clip.times)
        poses += clip_poses(body, clip, np.linspace(0.0, 1.0, max(2, n // step)), in_place)
    return poses
