"""Tracking control (paper 003, section 6): acceleration-based PD tracking and physical effects.

Equations 2-4, one gain set for every joint (accelerations, not torques, so no per-joint gains):

    qdd_i = k (q_target,i - q_i) - d qd_i          (2)  rotation difference as a rotation vector
    pdd_root = k (p_target,root - p_root) - d pd_root  (3)
    qd_i = dt qdd_i + qd_i',  q_i = dt qd_i (+) q_i'   (4)  semi-implicit Euler, quaternion update

Gains: k = 100 s^-2, d = 20 s^-1 (critically damped, natural frequency 10 rad/s), integrated in
2 substeps per 30 fps frame (one Euler step of a whole frame moves k dt^2 = a quarter of any
jump at once). Measured at the mode switches of punch, kick, spin kick, jump and wave (target
jumps of 70-135 degrees): k = 225 in one step moved a joint up to 34 degrees in one frame, k = 100
in 2 or 4 substeps at most ~16 degrees (2 cost half as much); a still posture is reached within
about 0.5 s.

Equations 6-7, the physical effect: for each joint, from the physics engine's rotations,

    dq_i = s1 dq_i' + s2 ((q_sim,i - q_sim,i') - (q_i - q_i'))                   (6)
    q_output,i = q_i + dq_i   on segments neither touched nor on the ground         (7)

q_i being the acceleration-tracked rotation (equation 4), which the simulation also follows.

The paper gives s1 = 0.2 dt and s2 = 0.5 dt; read with dt in frames of its 30 fps loop (dt = 1),
that is an effect that keeps a fifth of itself each frame and adds half the simulated change,
scaled here by the step length in frames. The tracked pose's own change is subtracted from the
simulated change so only what physics adds (sway, overshoot, a limb shaken by the rest) is
extracted: the plain simulated change would add the motion tracking already produces a second
time. Measured against the equation as printed (bench/touch_pose_effect.py; untouched arm's
sway from the tracked pose, median / largest, then the largest joint turn in one output frame
beyond the tracked pose's own, degrees; hand shaken 1 Hz | punch | pelvis dragged sideways):

    dt in frames, tracked change subtracted (this) 3.3 / 9.2, 3.4 | 0.6 / 5.4, 13.1 | 1.3 / 4.0, 3.5
    dt in frames, simulated change as it is        3.6 / 5.9, 5.6 | 0.8 / 6.9, 14.2 | 1.3 / 4.1, 3.5
    dt in seconds (s1 = 0.0067, s2 = 0.017 a frame) 0.1 / 0.2, 0.1 | 0.0 / 0.2, 0.4 | 0.0 / 0.1, 0.1

Read with dt in seconds the effect is a tenth of a degree, no visible shaking at all (the
paper's purpose); in frames both readings sway the free arm by degrees, and subtracting the
tracked change moves joints less abruptly (extra turn 3.4 against 5.6 degrees a frame with the
hand shaken, 13.1 against 14.2 in the punch), so it is kept.
The simulation follows the tracked pose rather than the raw target, whose jumps at mode
switches would yank the simulated body (measured: up to +13 degrees a frame on top of tracking).
"""

from __future__ import annotations

import numpy as np

from behaviors.motion.clips import (quat_conj, quat_from_rotvec, quat_left_matrix, quat_mul,
                                    quat_normalize, quat_to_rotvec)
from behaviors.touch_pose.humanoid import SEGMENTS, Humanoid, Pose

K_GAIN = 100.0
D_GAIN = 20.0
SUBSTEPS = 2
S1 = 0.2
S2 = 0.5
FRAME = 1.0 / 30.0


def rot_diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3) of a - b for quaternions (..., 4): the rotation taking b to a."""
    return quat_to_rotvec(quat_mul(a, quat_conj(b)))


class Tracker:
    """Acceleration-based tracking state: joint rotations and velocities, root position/velocity."""

    def __init__(self, pose: Pose, k: float = K_GAIN, d: float = D_GAIN) -> None:
        self.pose = pose.copy()
        self.omega = np.zeros((len(pose.rots), 3))
        self.vel = np.zeros(3)
        self.k, self.d = float(k), float(d)

    def step(self, target: Pose, dt: float) -> Pose:
        """Equations 2-4 for one step of ``dt`` seconds toward ``target``; returns the new pose."""
        h = dt / SUBSTEPS
        # q_target q^-1 as one matrix product per substep: the target's left-multiplication
        # matrices are built once per step
        left = quat_left_matrix(target.rots)
        for _ in range(SUBSTEPS):
            rel = np.matmul(left, quat_conj(self.pose.rots)[..., None])[..., 0]
            acc = self.k * quat_to_rotvec(rel) - self.d * self.omega                    # (2)
            pacc = self.k * (target.root - self.pose.root) - self.d * self.vel             # (3)
            self.omega = self.omega + h * acc                                             # (4)
            self.vel = self.vel + h * pacc
            self.pose.rots = quat_mul(quat_from_rotvec(h * self.omega), self.pose.rots)
            self.pose.root = self.pose.root + h * self.vel
        self.pose.rots = quat_normalize(self.pose.rots)
        return self.pose.copy()


class PhysicalEffect:
    """Equation 6's accumulated effect per joint (and the root) from successive simulated poses."""

    def __init__(self, n_joints: int) -> None:
        self.dq = np.zeros((n_joints, 3))
        self.dp = np.zeros(3)
        self._sim: Pose | None = None
        self._target: Pose | None = None

    def update(self, sim: Pose, target: Pose, dt: float) -> None:
        """Accumulate one step of ``dt`` seconds (equation 6) from the simulated and target
        poses."""
        if self._sim is not None and self._target is not None:
            f = dt / FRAME
            s1 = min(S1 * f, 1.0)
            both = rot_diff(np.stack([sim.rots, target.rots]),
                            np.stack([self._sim.rots, self._target.rots]))
            change = both[0] - both[1]
            self.dq = s1 * self.dq + S2 * f * change
            pchange = (sim.root - self._sim.root) - (target.root - self._target.root)
            self.dp = s1 * self.dp + S2 * f * pchange
        self._sim, self._target = sim.copy(), target.copy()

    def reset(self) -> None:
        self.dq[:] = 0.0
        self.dp[:] = 0.0
        self._sim = self._target = None


def free_segments(touched_parts: set[str], grounded: set[str]) -> set[str]:
    """Segments that take the physical effect: not controlled by a touch, not on the ground."""
    owner = {"head": "torso", "pelvis": "torso", "right_hand": "right_arm",
             "left_hand": "left_arm", "right_foot": "right_leg", "left_foot": "left_leg"}
    held = {owner[p] for p in touched_parts} | {owner[p] for p in grounded}
    return set(SEGMENTS) - held


def apply_effect(body: Humanoid, pose: Pose, effect: PhysicalEffect, segments: set[str]) -> Pose:
    """Equation 7: the effect added to the joints of ``segments`` (the torso includes the root)."""
    out = pose.copy()
    idx = _segment_joints(body, frozenset(segments))
    if idx:
        out.rots[idx] = quat_normalize(quat_mul(quat_from_rotvec(effect.dq[idx]), out.rots[idx]))
        body.clamp_many(out.rots, idx)
    if "torso" in segments:
        out.root = out.root + effect.dp
    return out


_JOINTS_OF: dict[tuple[int, frozenset], list[int]] = {}


def _segment_joints(body: Humanoid, segments: frozenset) -> list[int]:
    """Joint indices of ``segments`` (remembered: there are 32 combinations)."""
    key = (id(body), segments)
    if key not in _JOINTS_OF:
        _JOINTS_OF[key] = [body.names.index(j) for s in sorted(segments) for j in SEGMENTS[s]]
    return _JOINTS_OF[key]
