"""Cyclic coordinate descent IK (Welman 1993) on the humanoid, within joint limits (section 4).

Each goal moves one body part: its chain of joints, from the part up towards the chest, is turned
joint by joint so the part points at the goal (hinges only about their axis), every joint kept
within its limit after each turn. The pelvis is moved by translating the root; a head that neck
and chest cannot bring to its goal (it must rise or sink) moves the pelvis too. Section 4 limits
the correction to 0.2 m (:data:`MAX_CORRECTION`): a goal farther than that from where the blended
posture holds the part is pulled back to 0.2 m, so IK never drags a limb into an unnatural pose.

A hand or foot asked beyond its limb's reach leaves the pelvis where the blend puts it; section 4
fixes the planted feet and never translates the root. Measured alternative
(bench/touch_pose_posing.py, the pelvis moved by the weighted mean of what the unreached touched
parts and the planted feet, weight 4, still miss, each move capped at 0.2 m and followed by a
sweep): one finger's p90 gap 0.0027 -> 0.0019 m in place and 0.0105 -> 0.0056 m on shifted postures
(table m), several fingers 0.0091 -> 0.0058 / 0.0216 -> 0.0192; but the pelvis moves 0.40 / 0.80 m
in all for a hand goal 1 / 2 m away (0.234 m with a hand held through an action), beyond section
4's 0.2 m, and the untouched planted foot, re-planted each frame where the last frame left it,
creeps 0.023 / 0.037 / 0.052 m after three fingers' circles 1 / 2 / 3 (0.001 / 0.003 / 0.005 with
the pelvis kept), so the character walks away by its feet. With it, section 4's relative root
posing (bounded to 0.15 m and 30 degrees) still blends postures asked for in place worse (median
0.035 -> 0.040) and leaves several fingers farther (p90 0.0058 -> 0.0085), so samples stay in place
(:mod:`behaviors.touch_pose.samples`).
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

from behaviors.touch_pose.humanoid import PARTS, Humanoid, Pose, qmul as _qmul, qrot as _qrot

#: Largest distance (metres of the character's scale) IK may move a part away from the blend.
MAX_CORRECTION = 0.2
#: Joints turned for each part, nearest the part first.
CHAINS = {"right_hand": ("right_elbow", "right_shoulder", "chest"),
          "left_hand": ("left_elbow", "left_shoulder", "chest"),
          "right_foot": ("right_knee", "right_hip"),
          "left_foot": ("left_knee", "left_hip"),
          "head": ("neck", "chest")}


def limit_goal(current: np.ndarray, goal: np.ndarray, limit: float = MAX_CORRECTION) -> np.ndarray:
    """``goal`` pulled back to at most ``limit`` metres from ``current``."""
    d = np.asarray(goal, dtype=float) - current
    n = float(np.linalg.norm(d))
    return goal if n <= limit else current + d * (limit / n)


def _qaxis(axis: Sequence[float], angle: float) -> tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) turning ``angle`` radians about the unit ``axis``."""
    s = math.sin(angle / 2)
    return (math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s)


#: The joints of each foot's leg, hip first.
LEGS = {"right_foot": ("right_hip", "right_knee", "right_ankle"),
        "left_foot": ("left_hip", "left_knee", "left_ankle")}
#: A planted foot farther than this from its goal after CCD (metres of the character's scale)
#: is solved again from the leg as it stood.
REPLANT = 0.01


class CCD:
    """CCD solver for one humanoid. Every chain hangs from the pelvis, which CCD never turns, so
    each chain is solved from the pelvis transform in plain floating point (a few microseconds
    per joint turn instead of a numpy forward kinematics each time)."""

    def __init__(self, body: Humanoid, iterations: int = 8, tolerance: float = 0.003) -> None:
        self.body = body
        self.iterations = iterations
        self.tolerance = tolerance
        idx = {n: i for i, n in enumerate(body.names)}
        self.chains = {p: [idx[j] for j in js] for p, js in CHAINS.items()}
        self.legs = {f: [idx[j] for j in js] for f, js in LEGS.items()}
        self._part_index = {p: k for k, p in enumerate(PARTS)}
        self.paths: dict[str, list[int]] = {}
        for part, chain in self.chains.items():
            path = [body.part_body[part]]
            while path[-1] != chain[-1]:
                path.append(int(body.parent[path[-1]]))
            path.reverse()  # chain top (child of the pelvis) ... the part's body
            assert int(body.parent[path[0]]) == 0
            self.paths[part] = path
        self._chest = idx["chest"]
        self._offset = [tuple(o) for o in body.offset.tolist()]
        self._axis = [tuple(a) for a in body.axis.tolist()]
        self._part_off = {p: tuple(np.asarray(o, dtype=float).tolist())
                          for p, o in body.part_offset.items()}
        # plain-Python copies of what the inner loop reads (numpy scalar indexing costs ~0.1 us
        # a time, several hundred times a frame)
        self._hinge = [bool(h) for h in body.hinge]
        self._limit = [float(v) for v in body.limit]
        self._cos_half = [math.cos(v / 2) for v in self._limit]
        self._sin_half = [math.sin(v / 2) for v in self._limit]
        self._lo = [float(v) for v in body.hinge_lo]
        self._hi = [float(v) for v in body.hinge_hi]
        #: per part: (joint, its place on the path) in CCD order, nearest the part first
        self._order = {p: [(j, self.paths[p].index(j)) for j in js]
                       for p, js in self.chains.items()}

    def solve(self, pose: Pose, goals: Mapping[str, np.ndarray], legs: bool = False) -> Pose:
        """``pose`` (a copy) with each part in ``goals`` (part -> model-frame point) moved towards
        its goal; the pelvis goal translates the root first. With ``legs``, a foot CCD leaves
        over :data:`REPLANT` from its goal is placed by the leg's own IK (:meth:`_replanted`)."""
        out = self._solve(pose, goals)
        return self._replanted(out, goals) if legs else out

    def _replanted(self, out: Pose, goals: Mapping[str, np.ndarray]) -> Pose:
        """``out`` with each foot left over :data:`REPLANT` from its goal placed by its leg: the
        knee bent to the goal's distance from the hip (:meth:`_bend`), the hip turned toward it
        (:meth:`_aim`); kept when the goals are missed by less in all.
        Section 4 fixes the planted feet by IK, but CCD stalls on a straight leg whose goal is
        nearer the hip (a crouching sample's pelvis 0.12 m lower: the foot was left 0.14 m off,
        under the ground, the other lifted past the ground height and let go). Planted feet
        under drags of each part 0.1 m four ways from three views (48, physics off, 0.3 m tall):
        drags with a foot moved over 0.01 m 41 -> 30, with a foot under the ground 32 -> 4,
        median foot move 0.037 -> 0.025 m (the largest, 0.077 m, the pelvis lifted past the
        legs' reach, unchanged); bench/touch_pose_posing.py's drag gaps p90 0.0027 -> 0.0021
        (in place), 0.0044 -> 0.0023 and 0.0053 -> 0.0038 (several fingers), drift unchanged;
        held-out views 60,30 and 250,25: a foot under the ground 21 -> 3. Its price, taken for
        feet that stay on the floor: bench/touch_pose_turns.py's jump output 7.4 -> 8.1 degrees
        in one frame (bent planted legs start farther from the clip's first pose), punch 13.1
        -> 13.2; bench/touch_pose_effect.py's pelvis sway a second after the fingers lift 0.70
        -> 0.87 degrees (the punch's extra turn 13.1 -> 4.9)."""
        parts = self.body.parts(out)
        missed = [f for f in LEGS if f in goals and
                  np.linalg.norm(parts[self._part_index[f]] - goals[f]) > REPLANT]
        if not missed:
            return out
        retry = out.copy()
        local = [tuple(q) for q in retry.rots.tolist()]
        p0 = tuple(retry.root.tolist())
        for foot in missed:
            self._bend(foot, goals[foot], local, p0)
            self._aim(foot, goals[foot], local, p0)
        retry.rots = np.array(local)
        again = self.body.parts(retry)

        def miss(ps: np.ndarray) -> float:
            return sum(float(np.linalg.norm(ps[self._part_index[p]] - g))
                       for p, g in goals.items() if p in self._part_index)
        return retry if miss(again) < miss(parts) else out

    def _within_limit(self, q: tuple, j: int) -> tuple:
        """The local rotation ``q`` (w, x, y, z) of joint ``j``, its turn cut to the joint's limit
        (radians) about the same axis."""
        if 2.0 * math.acos(min(1.0, abs(q[0]))) <= self._limit[j]:
            return q
        n = math.sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
        k = (1.0 if q[0] >= 0 else -1.0) * self._sin_half[j] / n
        return (self._cos_half[j], q[1] * k, q[2] * k, q[3] * k)

    def _bend(self, foot: str, goal: np.ndarray, local: list, p0: tuple) -> None:
        """Bend ``foot``'s knee (in place on ``local``) so the foot lies as far from the hip as
        ``goal`` (bisection between the straight leg and the knee's limit). CCD cannot: with the
        leg straight and the goal nearer the hip, the knee's turn toward it is a hyperextension,
        clamped to its limit, and the hip's turn then points the straight leg past the goal."""
        hip, knee, _ = self.legs[foot]
        o = _qrot(local[0], self._offset[hip])
        at = np.add(p0, o)
        want = float(np.linalg.norm(np.asarray(goal) - at))
        axis = self._axis[knee]

        def reach(angle: float) -> float:
            local[knee] = _qaxis(axis, angle)
            return float(np.linalg.norm(np.subtract(self._effector(foot, local, local[0], p0),
                                                    at)))
        # from the straight leg (0, the farthest reach) to the knee's bent limit (the nearest)
        lo, hi = self._lo[knee], min(0.0, self._hi[knee])
        if reach(hi) <= want:      # the goal beyond reach: the leg straight
            return
        for _ in range(24):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if reach(mid) > want else (mid, hi)
        local[knee] = _qaxis(axis, 0.5 * (lo + hi))

    def _aim(self, foot: str, goal: np.ndarray, local: list, p0: tuple) -> None:
        """Turn ``foot``'s hip (in place on ``local``, the shortest turn, within its limit) so
        the leg points from the hip at ``goal``."""
        hip = self.legs[foot][0]
        q0 = local[0]
        at = np.add(p0, _qrot(q0, self._offset[hip]))
        v1 = np.subtract(self._effector(foot, local, q0, p0), at)
        v2 = np.asarray(goal, dtype=float) - at
        c = np.cross(v1, v2)
        s = float(np.linalg.norm(c))
        ang = math.atan2(s, float(v1 @ v2))
        if s < 1e-9 or ang < 1e-6:
            return
        la = _qrot((q0[0], -q0[1], -q0[2], -q0[3]), tuple((c / s).tolist()))
        local[hip] = self._within_limit(_qmul(_qaxis(la, ang), local[hip]), hip)

    def _solve(self, pose: Pose, goals: Mapping[str, np.ndarray]) -> Pose:
        out = pose.copy()
        if "pelvis" in goals:
            out.root = np.asarray(goals["pelvis"], dtype=float).copy()
        items = [(p, tuple(np.asarray(g, dtype=float).tolist())) for p, g in goals.items()
                 if p in self.chains]
        if not items:
            return out
        local = [tuple(q) for q in out.rots.tolist()]
        q0 = local[0]
        p0 = tuple(out.root.tolist())
        left = {part: math.inf for part, _ in items}
        previous = math.inf
        # the chest is shared: when the head is held, the hands' chains stop at the shoulders
        # (otherwise hands and head undo each other's chest turns every sweep)
        skip = self._chest if "head" in left and len(left) > 1 else -1
        shifted = np.zeros(3)
        head = dict(items).get("head") if "pelvis" not in goals else None
        for _ in range(self.iterations):
            for part, goal in items:
                if left[part] > self.tolerance:
                    left[part] = self._chain(part, goal, local, q0, p0, skip)
            worst = max(left.values())
            if head is not None and left["head"] > self.tolerance and previous - worst < 0.01:
                # the neck and chest cannot bring the head there (it must rise or sink): move
                # the pelvis by what is left, within the same 0.2 m, and sweep again (the
                # planted feet's chains follow)
                miss = np.subtract(head, self._effector("head", local, q0, p0))
                step = limit_goal(shifted, shifted + miss) - shifted
                if np.linalg.norm(step) > 0.5 * self.tolerance:
                    shifted += step
                    p0 = tuple(np.add(p0, step).tolist())
                    left = {part: math.inf for part in left}
                    previous = math.inf
                    continue
            # done, or stalled (a goal out of reach: further sweeps would not bring it closer)
            if worst < self.tolerance or previous - worst < 0.1 * self.tolerance:
                break
            previous = worst
        out.rots = np.array(local)
        out.root = np.array(p0)
        return out

    def _effector(self, part: str, local: list, q0: tuple, p0: tuple) -> tuple:
        """World position of ``part`` for joint rotations ``local`` and pelvis ``q0``, ``p0``."""
        q, p = q0, p0
        for b in self.paths[part]:
            o = _qrot(q, self._offset[b])
            p = (p[0] + o[0], p[1] + o[1], p[2] + o[2])
            q = _qmul(q, local[b])
        o = _qrot(q, self._part_off[part])
        return (p[0] + o[0], p[1] + o[1], p[2] + o[2])

    def _chain(self, part: str, goal: tuple, local: list, q0: tuple, p0: tuple,
               skip: int = -1) -> float:
        """One CCD sweep of ``part``'s chain (in place on ``local``); the remaining distance."""
        path = self.paths[part]
        ox, oy, oz = self._part_off[part]
        offset, axes = self._offset, self._axis
        gx, gy, gz = goal
        # world orientation and position of each path body (lists along the path)
        qw, pw = [], []
        pq, pp = q0, p0
        for b in path:
            o = _qrot(pq, offset[b])
            pp = (pp[0] + o[0], pp[1] + o[1], pp[2] + o[2])
            pq = _qmul(pq, local[b])
            pw.append(pp)
            qw.append(pq)
        o = _qrot(qw[-1], (ox, oy, oz))
        ex, ey, ez = pw[-1][0] + o[0], pw[-1][1] + o[1], pw[-1][2] + o[2]
        dist = math.sqrt((ex - gx) ** 2 + (ey - gy) ** 2 + (ez - gz) ** 2)
        if dist < self.tolerance:
            return dist  # already there (a planted foot, mostly)
        for j, k0 in self._order[part]:
            if j == skip and part != "head":
                continue
            pj = pw[k0]
            v1 = (ex - pj[0], ey - pj[1], ez - pj[2])
            v2 = (gx - pj[0], gy - pj[1], gz - pj[2])
            qp = qw[k0 - 1] if k0 > 0 else q0
            if self._hinge[j]:
                a = _qrot(qw[k0], axes[j])
                d1 = v1[0] * a[0] + v1[1] * a[1] + v1[2] * a[2]
                d2 = v2[0] * a[0] + v2[1] * a[1] + v2[2] * a[2]
                a1 = (v1[0] - a[0] * d1, v1[1] - a[1] * d1, v1[2] - a[2] * d1)
                a2 = (v2[0] - a[0] * d2, v2[1] - a[1] * d2, v2[2] - a[2] * d2)
                cx = a1[1] * a2[2] - a1[2] * a2[1]
                cy = a1[2] * a2[0] - a1[0] * a2[2]
                cz = a1[0] * a2[1] - a1[1] * a2[0]
                ang = math.atan2(cx * a[0] + cy * a[1] + cz * a[2],
                                 a1[0] * a2[0] + a1[1] * a2[1] + a1[2] * a2[2])
                q = local[j]
                ax = axes[j]
                old = 2.0 * math.atan2(q[1] * ax[0] + q[2] * ax[1] + q[3] * ax[2], q[0])
                old = (old + math.pi) % (2 * math.pi) - math.pi
                new = min(max(old + ang, self._lo[j]), self._hi[j])
                local[j] = _qaxis(ax, new)
            else:
                cx = v1[1] * v2[2] - v1[2] * v2[1]
                cy = v1[2] * v2[0] - v1[0] * v2[2]
                cz = v1[0] * v2[1] - v1[1] * v2[0]
                s = math.sqrt(cx * cx + cy * cy + cz * cz)
                ang = math.atan2(s, v1[0] * v2[0] + v1[1] * v2[1] + v1[2] * v2[2])
                if s < 1e-9 or ang < 1e-6:
                    continue
                la = _qrot((qp[0], -qp[1], -qp[2], -qp[3]), (cx / s, cy / s, cz / s))
                local[j] = self._within_limit(_qmul(_qaxis(la, ang), local[j]), j)
            # forward kinematics below j along the path, then the part
            pq = qw[k0 - 1] if k0 > 0 else q0
            pp = pw[k0 - 1] if k0 > 0 else p0
            for k in range(k0, len(path)):
                b = path[k]
                o = _qrot(pq, offset[b])
                pp = (pp[0] + o[0], pp[1] + o[1], pp[2] + o[2])
                pq = _qmul(pq, local[b])
                pw[k] = pp
                qw[k] = pq
            o = _qrot(pq, (ox, oy, oz))
            ex, ey, ez = pp[0] + o[0], pp[1] + o[1], pp[2] + o[2]
        return math.sqrt((ex - gx) ** 2 + (ey - gy) ** 2 + (ez - gz) ** 2)
