"""Physics engines for touch-pose secondary motion (paper 003, equation 5): pybullet vs MuJoCo.

Both simulate the same humanoid (pybullet: DeepMimic's ``humanoid.urdf``; MuJoCo: an MJCF built
here from the same skeleton, capsules per bone with pybullet's link masses), free-floating over
a ground plane under gravity, each segment pulled to where the tracked posture holds it by
f = m (k (p_target - p) - d v) with k = 400, d = 30, two substeps of 1/60 s per 30 fps frame.
The tracked posture (equations 2-4) follows the punch, kick and spin kick clips in turn. Figures:
CPU milliseconds per frame (median, p99), the largest and median distance between a simulated
segment and its target, how often the body had to be put back, and how far any simulated joint
turned in one frame beyond the tracked pose's own turn (p99 and largest): the secondary motion taken
from the simulation, which must stay small for a stable engine. Runs interleaved
(A B A B). MuJoCo is not a dependency: without it (``pip install mujoco==3.3.0``) only pybullet
is measured.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit, stats_ms  # noqa: E402
from behaviors.motion.clips import quat_from_axis_angle, quat_normalize  # noqa: E402
from behaviors.touch_pose.humanoid import Humanoid, Pose, qrot  # noqa: E402
from behaviors.touch_pose.physics import (D_PHYS, K_PHYS, RESET_DISTANCE,  # noqa: E402
                                          SUBSTEP, Physics)
from behaviors.touch_pose.tracking import rot_diff  # noqa: E402
from behaviors.touch_pose.samples import clip_named, clip_poses  # noqa: E402
from behaviors.touch_pose.tracking import Tracker  # noqa: E402

DT = 1.0 / 30.0

#: Segment masses (kg) of pybullet's DeepMimic humanoid, in :data:`Humanoid.names` order.
LINK_MASS = np.array([6.0, 14.0, 2.0, 4.5, 3.0, 1.0, 1.5, 1.0, 4.5, 3.0, 1.0, 1.5, 1.0])


class MujocoPhysics:
    """The humanoid in MuJoCo with equation 5's segment forces (same gains as pybullet)."""

    def __init__(self, body: Humanoid, masses: np.ndarray | None = None) -> None:
        import mujoco
        masses = LINK_MASS if masses is None else masses
        self.mj = mujoco
        self.body = body
        kids = {i: [c for c in range(len(body.names)) if body.parent[c] == i]
                for i in range(len(body.names))}

        def tip(i: int) -> np.ndarray:
            if kids[i]:
                return np.mean([body.offset[c] for c in kids[i]], axis=0)
            for p, b in body.part_body.items():
                if b == i:
                    return body.part_offset[p]
            return np.zeros(3)

        def xml(i: int, depth: int) -> str:
            name = body.names[i]
            pos = " ".join(f"{v:.5f}" for v in body.offset[i])
            if i == 0:
                joint = '<freejoint name="root"/>'
            elif body.hinge[i]:
                ax = " ".join(f"{v:g}" for v in body.axis[i])
                joint = f'<joint name="{name}" type="hinge" axis="{ax}" limited="false"/>'
            else:
                joint = f'<joint name="{name}" type="ball"/>'
            t = tip(i)
            if np.linalg.norm(t) > 1e-6:
                geom = (f'<geom type="capsule" fromto="0 0 0 {t[0]:.5f} {t[1]:.5f} {t[2]:.5f}" '
                        f'size="0.04" mass="{masses[i]:.4f}"/>')
            else:
                geom = f'<geom type="sphere" size="0.06" mass="{masses[i]:.4f}"/>'
            inner = "".join(xml(c, depth + 1) for c in kids[i])
            if name.endswith("_elbow"):  # the hand: a welded body, as pybullet's wrist link
                w = " ".join(f"{v:.5f}" for v in body.part_offset["right_hand"])
                inner += (f'<body name="{name[:-6]}_wrist" pos="{w}">'
                          '<geom type="sphere" size="0.04" mass="0.5"/></body>')
            return f'<body name="{name}" pos="{pos}">{joint}{geom}{inner}</body>'

        model = (f'<mujoco><option timestep="{SUBSTEP:.6f}" gravity="0 -9.8 0"/>'
                 '<worldbody><geom type="plane" size="10 10 0.1" zaxis="0 1 0" friction="0.9"/>'
                 f'{xml(0, 0)}</worldbody></mujoco>')
        self.model = mujoco.MjModel.from_xml_string(model)
        self.data = mujoco.MjData(self.model)
        self.qids = [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, n) for n in body.names]
        self.ids = self.qids + [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, n)
                                for n in ("right_wrist", "left_wrist")]
        self.mass = self.model.body_mass[self.ids]
        self.ipos = [tuple(self.model.body_ipos[i]) for i in self.qids]
        wrist = tuple(float(v) for v in body.part_offset["right_hand"])
        self._frames = list(range(len(body.names))) + [body.names.index("right_elbow"),
                                                       body.names.index("left_elbow")]
        self._com_off = self.ipos + [wrist, wrist]
        self.qadr = [int(self.model.jnt_qposadr[self.model.body_jntadr[i]]) for i in self.qids]
        self.resets = 0
        self.started = False
        self._vel = np.zeros(6)

    def set_pose(self, pose: Pose) -> None:
        d, b = self.data, self.body
        d.qvel[:] = 0.0
        d.qpos[0:3] = pose.root
        d.qpos[3:7] = pose.rots[0]
        for i in range(1, len(b.names)):
            a = self.qadr[i]
            if b.hinge[i]:
                d.qpos[a] = b.hinge_angle(pose.rots, i)
            else:
                d.qpos[a:a + 4] = pose.rots[i]
        self.mj.mj_forward(self.model, d)

    def targets(self, pose: Pose) -> np.ndarray:
        qw, pw = self.body.globals(pose)
        return np.array([np.add(pw[b], qrot(qw[b], off))
                         for b, off in zip(self._frames, self._com_off)])

    def step(self, target: Pose, dt: float) -> Pose:
        """Simulate ``dt`` seconds pulled toward ``target`` (equation 5); the simulated pose."""
        if not self.started:
            self.set_pose(target)
            self.started = True
        goal = self.targets(target)
        d = self.data
        for _ in range(max(1, int(round(dt / SUBSTEP)))):
            p = d.xipos[self.ids].copy()
            v = np.empty((len(self.ids), 3))
            for k, i in enumerate(self.ids):  # each segment's centre-of-mass velocity, world frame
                self.mj.mj_objectVelocity(self.model, d, self.mj.mjtObj.mjOBJ_XBODY, i,
                                          self._vel, 0)
                v[k] = self._vel[3:]
            if np.max(np.linalg.norm(p - goal, axis=1)) > RESET_DISTANCE:
                self.set_pose(target)
                self.resets += 1
                continue
            d.xfrc_applied[self.ids, :3] = self.mass[:, None] * (K_PHYS * (goal - p) - D_PHYS * v)
            self.mj.mj_step(self.model, d)
        return self.read()

    def read(self) -> Pose:
        """The simulated pose."""
        d, b = self.data, self.body
        rots = np.empty((len(b.names), 4))
        rots[0] = d.qpos[3:7]
        for i in range(1, len(b.names)):
            a = self.qadr[i]
            rots[i] = (quat_from_axis_angle(b.axis[i], float(d.qpos[a])) if b.hinge[i]
                       else d.qpos[a:a + 4])
        return Pose(d.qpos[0:3].copy(), quat_normalize(rots))

    def close(self) -> None:
        pass

    def error(self, target: Pose) -> float:
        off = self.data.xipos[self.ids] - self.targets(target)
        return float(np.max(np.linalg.norm(off, axis=1)))




def pybullet_error(phys: Physics, target: Pose) -> float:
    states = phys.pb.getLinkStates(phys.uid, phys.links, physicsClientId=phys.client)
    p = np.array([s[0] for s in states])
    return float(np.max(np.linalg.norm(p - phys.targets(target), axis=1)))


def main() -> None:
    check_flags("touch_pose_physics", sys.argv[1:])
    body = Humanoid()
    poses: list[Pose] = []
    starts: set[int] = set()
    for name in ("punch", "kick", "spinkick"):
        clip = clip_named(name)
        raw = clip_poses(body, clip, np.linspace(0, 1, int(clip.duration * 30)))
        tracker = Tracker(raw[0])  # the simulation follows the acceleration-tracked pose
        starts.add(len(poses))
        poses += [tracker.step(p, DT) for p in raw]
    bullet = Physics(body)
    engines = {"pybullet": (bullet, lambda t: pybullet_error(bullet, t))}
    try:
        import mujoco

        masses = np.concatenate([[bullet.mass[0]], bullet.mass[1:len(body.names)]])
        mj = MujocoPhysics(body, masses)
        engines["mujoco"] = (mj, mj.error)
        mj_version = mujoco.__version__
    except ImportError:
        mj_version = None
    cpu = {k: [] for k in engines}
    err = {k: [] for k in engines}
    turn = {k: [] for k in engines}
    last: dict = {}
    for rep in range(3):
        for k, pose in enumerate(poses):
            for name, (eng, error) in engines.items():
                if k in starts:
                    eng.started = False  # each clip starts with the body put on its first pose
                resets = eng.resets
                c0 = time.thread_time()
                sim = eng.step(pose, DT)
                cpu[name].append(time.thread_time() - c0)
                err[name].append(error(pose))
                if name in last and eng.resets == resets and k not in starts:
                    # how far the simulated joints turn in one frame beyond the tracked pose
                    extra = (rot_diff(sim.rots, last[name][0].rots)
                             - rot_diff(pose.rots, last[name][1].rots))
                    turn[name].append(float(np.degrees(np.linalg.norm(extra, axis=1)).max()))
                last[name] = (sim, pose)
    figures: dict = {}
    for name in engines:
        for m, v in stats_ms(cpu[name]).items():
            figures[f"{name}_cpu_{m}"] = round(v, 4)
        figures[f"{name}_max_error_m"] = round(max(err[name]), 4)
        figures[f"{name}_median_error_m"] = round(float(np.median(err[name])), 4)
        figures[f"{name}_resets"] = engines[name][0].resets
        figures[f"{name}_extra_turn_p99_deg_per_frame"] = \
            round(float(np.percentile(turn[name], 99)), 2)
        figures[f"{name}_extra_turn_max_deg_per_frame"] = round(max(turn[name]), 2)
    figures["frames"] = len(cpu["pybullet"])
    figures["mujoco"] = mj_version or "not installed"
    import importlib.metadata as md
    figures["pybullet"] = md.version("pybullet")
    bullet.close()
    emit("touch_pose_physics", figures, {"pybullet_cpu_p99_ms": 5.0, "mujoco_cpu_p99_ms": 5.0})


if __name__ == "__main__":
    main()
