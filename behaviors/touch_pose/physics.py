"""Physics-based tracking for secondary motion (paper 003, section 6, equation 5) with pybullet.

The simulated body is pybullet's DeepMimic humanoid (the very URDF the skeleton comes from) at
the character's scale, free-floating, joints without motors, gravity along -y and a ground plane
at y = 0 with friction. Every substep each segment gets equation 5's force toward where the
tracked posture holds it,

    f_i = m_i (k (p_target,i - p_i) - d pd_i)                                      (5)

scaled by the segment's mass so one gain set moves light hands and the heavy chest alike
(k = 400 s^-2, d = 30 s^-1: a little under critical damping, so limbs sway and settle). Gravity
and the feet's contacts are the engine's. The body follows the acceleration-tracked pose.
Measured over punch, kick and spin kick at 30 fps (median / largest point error against the
tracked pose): k = 120 lagged 0.09-0.10 / 0.29-0.32 m and had to be put back 2-3 times per
action; k = 400 lagged 0.03-0.07 / 0.26-0.28 m, once per action; substeps of 1/120 s instead of
1/60 s changed nothing measurable at twice the cost, so 2 substeps per frame are used. A body
that drifts more than 0.5 m from its target is put back onto it, and that step's change is not
taken as a physical effect.

Engine choice, measured by ``bench/touch_pose_physics.py`` (both engines following the tracked
punch, kick and spin kick, interleaved, same gains and substeps; MuJoCo 3.3.0 with the same body
built as MJCF; two runs on a shared, loaded machine): MuJoCo took 0.47-0.86 ms CPU median /
1.1-1.3 ms p99 per frame against pybullet 3.2.7's 0.58-1.05 / 1.25-1.7 ms, but its joints turned
up to 176 degrees in a frame beyond the tracked pose (p99; ball joints and hinges spinning),
against 25 for pybullet, and in the engine its secondary
motion jerked hips and ankles by 60-90 degrees a frame. pybullet, stable and already a
dependency for the clips, is kept; MuJoCo is not a dependency.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
from typing import Iterator

import numpy as np

from behaviors.motion.clips import quat_normalize
from behaviors.motion.deepmimic import humanoid_urdf
from behaviors.touch_pose.humanoid import SCALE, Humanoid, Pose, qrot

K_PHYS = 400.0
D_PHYS = 30.0
SUBSTEP = 1.0 / 60.0
RESET_DISTANCE = 0.5


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """Silence the C library's own prints (pybullet's URDF warnings go straight to fd 1 and 2)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        os.dup2(null, 2)
        yield
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved + [null]:
            os.close(fd)


class Physics:
    """One pybullet world (DIRECT, no window) holding the humanoid and the ground."""

    def __init__(self, body: Humanoid) -> None:
        with _quiet():
            import pybullet as pb
            self.client = pb.connect(pb.DIRECT)
        self.pb = pb
        self.body = body
        c = self.client
        pb.setGravity(0, -9.8, 0, physicsClientId=c)
        pb.setTimeStep(SUBSTEP, physicsClientId=c)
        plane = pb.createCollisionShape(pb.GEOM_PLANE, planeNormal=[0, 1, 0], physicsClientId=c)
        self.ground = pb.createMultiBody(0, plane, physicsClientId=c)
        pb.changeDynamics(self.ground, -1, lateralFriction=0.9, physicsClientId=c)
        with _quiet():
            self.uid = pb.loadURDF(str(humanoid_urdf()), globalScaling=SCALE,
                                   flags=pb.URDF_MAINTAIN_LINK_ORDER, physicsClientId=c)
        names = {pb.getJointInfo(self.uid, j, physicsClientId=c)[1].decode(): j
                 for j in range(pb.getNumJoints(self.uid, physicsClientId=c))}
        self.joint_ids = [names[n] for n in body.names[1:]]
        self.links = [names["root"]] + self.joint_ids + [names["right_wrist"], names["left_wrist"]]
        self.mass = np.array([pb.getDynamicsInfo(self.uid, k, physicsClientId=c)[0]
                              for k in self.links])
        for j in self.joint_ids:
            name = pb.getJointInfo(self.uid, j, physicsClientId=c)[1].decode()
            if body.hinge[body.names.index(name)]:
                pb.setJointMotorControl2(self.uid, j, pb.VELOCITY_CONTROL, force=0,
                                         physicsClientId=c)
            else:
                pb.setJointMotorControlMultiDof(self.uid, j, pb.POSITION_CONTROL,
                                                targetPosition=[0, 0, 0, 1], positionGain=0,
                                                velocityGain=0, force=[0, 0, 0], physicsClientId=c)
            pb.changeDynamics(self.uid, j, lateralFriction=0.9, physicsClientId=c)
        # each link's centre of mass in its joint frame (link frame), from the rest pose
        self.set_pose(Pose(np.array([0.0, 2.0, 0.0]),
                           np.tile([1.0, 0, 0, 0], (len(body.names), 1))))
        states = pb.getLinkStates(self.uid, self.links, physicsClientId=c)
        self.com_local = []
        for s in states:
            r = np.array(pb.getMatrixFromQuaternion(s[5])).reshape(3, 3)
            self.com_local.append(r.T @ (np.array(s[0]) - np.array(s[4])))
        self.com_local = np.array(self.com_local)
        wrist = body.part_offset["right_hand"]
        i_re, i_le = body.names.index("right_elbow"), body.names.index("left_elbow")
        self._frames = list(range(len(body.names))) + [i_re, i_le]
        self._frame_off = [np.zeros(3)] * len(body.names) + [wrist, wrist]
        # centre of mass offsets in the frames of our bodies (the wrists hang off the elbows)
        self._com_off = [tuple((off + c).tolist())
                         for off, c in zip(self._frame_off, self.com_local)]
        self._hinge_axes = [tuple(body.axis[i].tolist()) if body.hinge[i] else None
                            for i in range(1, len(body.names))]
        self.started = False
        self.resets = 0

    def set_pose(self, pose: Pose) -> None:
        """Put the simulated body exactly on ``pose``, at rest."""
        pb, c = self.pb, self.client
        q = pose.rots
        pb.resetBasePositionAndOrientation(self.uid, pose.root.tolist(),
                                           [q[0, 1], q[0, 2], q[0, 3], q[0, 0]], physicsClientId=c)
        pb.resetBaseVelocity(self.uid, [0, 0, 0], [0, 0, 0], physicsClientId=c)
        values = []
        for i in range(1, len(self.body.names)):
            if self.body.hinge[i]:
                values.append([self.body.hinge_angle(q, i)])
            else:
                values.append([q[i, 1], q[i, 2], q[i, 3], q[i, 0]])
        pb.resetJointStatesMultiDof(self.uid, self.joint_ids, values, physicsClientId=c)

    def targets(self, pose: Pose) -> np.ndarray:
        """Target centres of mass (links, 3) of the segments for a tracked ``pose``."""
        qw, pw = self.body.globals(pose)
        out = []
        for b, off in zip(self._frames, self._com_off):
            o = qrot(qw[b], off)
            out.append((pw[b][0] + o[0], pw[b][1] + o[1], pw[b][2] + o[2]))
        return np.array(out)

    def step(self, target: Pose, dt: float) -> Pose:
        """Simulate ``dt`` seconds pulled toward ``target`` (equation 5); the simulated pose."""
        pb, c = self.pb, self.client
        goal = self.targets(target)
        if not self.started:
            self.set_pose(target)
            self.started = True
        n = max(1, int(round(dt / SUBSTEP)))
        apply, uid, world = pb.applyExternalForce, self.uid, pb.WORLD_FRAME
        for _ in range(n):
            states = pb.getLinkStates(uid, self.links, computeLinkVelocity=1,
                                      physicsClientId=c)
            pv = np.array([s[0] + s[6] for s in states])  # positions then velocities (links, 6)
            p, v = pv[:, :3], pv[:, 3:]
            err = p - goal
            worst = float(np.einsum("ij,ij->i", err, err).max())
            if not math.isfinite(worst) or worst > RESET_DISTANCE ** 2:
                self.set_pose(target)
                self.resets += 1
                continue
            force = (self.mass[:, None] * (-K_PHYS * err - D_PHYS * v)).tolist()
            for link, f, at in zip(self.links, force, p.tolist()):
                apply(uid, link, f, at, world, physicsClientId=c)
            pb.stepSimulation(physicsClientId=c)
        return self.read()

    def read(self) -> Pose:
        """The simulated pose."""
        pb, c = self.pb, self.client
        pos, orn = pb.getBasePositionAndOrientation(self.uid, physicsClientId=c)
        states = pb.getJointStatesMultiDof(self.uid, self.joint_ids, physicsClientId=c)
        rows = [(orn[3], orn[0], orn[1], orn[2])]
        for (v, *_), axis in zip(states, self._hinge_axes):
            if axis is not None:
                half = 0.5 * v[0]
                s = math.sin(half)
                rows.append((math.cos(half), s * axis[0], s * axis[1], s * axis[2]))
            else:
                rows.append((v[3], v[0], v[1], v[2]))
        return Pose(np.array(pos), quat_normalize(np.array(rows)))

    def close(self) -> None:
        try:
            self.pb.disconnect(physicsClientId=self.client)
        except Exception:  # already gone
            pass
