"""The articulated 3-D humanoid of touch-pose control (paper 003, section 3) and its virtual camera.

The humanoid is pybullet's DeepMimic ``humanoid.urdf`` (the skeleton its motion-capture clips
drive) at a quarter of its file units, so lengths are metres of the character's own scale (about
1.6 m tall) and the clips' root positions need no conversion. A pose is

- ``root``: pelvis position (3,), metres, in the model frame (x forward, y up, z to the right);
- ``rots``: (13, 4) unit quaternions (w first): row 0 the pelvis orientation, row i + 1 the local
  rotation of joint :data:`JOINTS` [i]. Knees and elbows are hinges: their quaternions turn about
  the hinge axis only.

:class:`Camera` is an orthographic virtual camera at azimuth/elevation around the character
(DESIGN.md: azimuth 0 in front of the character, 90 at its right-hand side; elevation above the
horizontal). A touch is a half-line from that camera; with an orthographic camera its distance
to a 3-D point equals the distance between the touch and the point's projection on the screen,
which is what the constraint distance of section 4 uses. Orthographic was chosen so the figure
keeps one scale on the table wherever it stands (a projector's view of a tabletop is flat).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from behaviors.motion.clips import Clip, quat_from_axis_angle, quat_normalize, quat_to_matrix
from behaviors.motion.deepmimic import humanoid_urdf
from behaviors.motion.skeleton import load_urdf

#: URDF units -> metres: pybullet's DeepMimic environment loads the humanoid at this scale.
SCALE = 0.25
JOINTS = ("chest", "neck", "right_hip", "right_knee", "right_ankle", "right_shoulder",
          "right_elbow", "left_hip", "left_knee", "left_ankle", "left_shoulder", "left_elbow")
HINGES = ("right_knee", "right_elbow", "left_knee", "left_elbow")
#: Touchable body parts (DESIGN.md names): each is a point fixed to one body.
PARTS = ("head", "pelvis", "left_hand", "right_hand", "left_foot", "right_foot")
#: The five segments of section 6 (equation 7): which joints each one holds.
SEGMENTS = {"torso": ("root", "chest", "neck"),
            "right_leg": ("right_hip", "right_knee", "right_ankle"),
            "left_leg": ("left_hip", "left_knee", "left_ankle"),
            "right_arm": ("right_shoulder", "right_elbow"),
            "left_arm": ("left_shoulder", "left_elbow")}
#: Joint limits: largest rotation from the rest pose (degrees) for ball joints, (min, max) radians
#: for hinges. Set just outside what the 15 DeepMimic clips reach (measured: chest 75, neck 79,
#: hips 145, ankles 64, shoulders 158 degrees; knees -2.76..0.22, elbows 0..2.42 radians).
BALL_LIMIT_DEG = {"chest": 80.0, "neck": 85.0, "right_hip": 150.0, "left_hip": 150.0,
                  "right_ankle": 70.0, "left_ankle": 70.0, "right_shoulder": 170.0,
                  "left_shoulder": 170.0}
HINGE_RANGE = {"right_knee": (-2.9, 0.25), "left_knee": (-2.9, 0.25),
               "right_elbow": (0.0, 2.6), "left_elbow": (0.0, 2.6)}
#: Model (x forward, y up, z right) -> world (x forward, y left, z up), as DESIGN.md's z-up joints.
MODEL_TO_WORLD = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def qmul(a: tuple, b: tuple) -> tuple:
    """Hamilton product of two quaternions given as float tuples (w, x, y, z)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def qrot(q: tuple, v: tuple) -> tuple:
    """Vector ``v`` turned by the unit quaternion ``q`` (float tuples)."""
    w, x, y, z = q
    vx, vy, vz = v
    tx = 2.0 * (y * vz - z * vy)
    ty = 2.0 * (z * vx - x * vz)
    tz = 2.0 * (x * vy - y * vx)
    return (vx + w * tx + y * tz - z * ty, vy + w * ty + z * tx - x * tz,
            vz + w * tz + x * ty - y * tx)


@dataclass
class Pose:
    """A humanoid pose: ``root`` (3,) metres in the model frame, ``rots`` (13, 4) quaternions."""

    root: np.ndarray
    rots: np.ndarray

    def copy(self) -> "Pose":
        return Pose(self.root.copy(), self.rots.copy())


class Humanoid:
    """Joint hierarchy, bone lengths (metres), hinge axes, limits and forward kinematics."""

    def __init__(self) -> None:
        skel = load_urdf(humanoid_urdf())
        by_name = {j.name: j for j in skel.joints}
        child_of = {j.child: j.name for j in skel.joints}
        self.names = ("root",) + JOINTS
        index = {n: i for i, n in enumerate(self.names)}
        self.parent = np.full(len(self.names), -1, dtype=int)
        self.offset = np.zeros((len(self.names), 3))
        self.axis = np.zeros((len(self.names), 3))
        for i, n in enumerate(JOINTS, start=1):
            j = by_name[n]
            parent_joint = child_of.get(j.parent, "root")
            self.parent[i] = index.get(parent_joint, 0)
            self.offset[i] = j.xyz * SCALE
            self.axis[i] = j.axis
        self.hinge = np.array([n in HINGES for n in self.names])
        self.children = [[c for c in range(len(self.names)) if self.parent[c] == i]
                         for i in range(len(self.names))]
        wrist = by_name["right_wrist"].xyz * SCALE
        head = skel.tips["neck"] * SCALE
        foot = skel.tips["right_ankle"] * SCALE
        # Part points: (body index, offset in that body's frame, metres).
        self.part_body = {"head": index["neck"], "pelvis": 0,
                          "left_hand": index["left_elbow"], "right_hand": index["right_elbow"],
                          "left_foot": index["left_ankle"], "right_foot": index["right_ankle"]}
        self.part_offset = {"head": 0.5 * head, "pelvis": np.zeros(3), "left_hand": wrist.copy(),
                            "right_hand": wrist.copy(), "left_foot": 0.5 * foot,
                            "right_foot": 0.5 * foot}
        self.part_index = {p: k for k, p in enumerate(PARTS)}
        self._pb_list = [int(self.part_body[p]) for p in PARTS]
        self._po_list = [tuple(float(v) for v in self.part_offset[p]) for p in PARTS]
        self._parent_list = [int(p) for p in self.parent]
        self._offset_list = [tuple(o) for o in self.offset.tolist()]
        #: Drawn segments between :meth:`points` rows (joints, then the parts' points).
        n = len(self.names)
        bones = [(int(self.parent[i]), i) for i in range(1, n)]
        bones += [(index["right_elbow"], n + self.part_index["right_hand"]),
                  (index["left_elbow"], n + self.part_index["left_hand"]),
                  (index["neck"], n + self.part_index["head"]),
                  (index["right_ankle"], n + self.part_index["right_foot"]),
                  (index["left_ankle"], n + self.part_index["left_foot"])]
        self.bones = tuple(bones)
        self.limit = np.array([math.radians(BALL_LIMIT_DEG.get(nm, 180.0)) for nm in self.names])
        self.hinge_lo = np.array([HINGE_RANGE.get(nm, (0.0, 0.0))[0] for nm in self.names])
        self.hinge_hi = np.array([HINGE_RANGE.get(nm, (0.0, 0.0))[1] for nm in self.names])
        self._clamp_split: dict[tuple, tuple] = {}

    # --- kinematics ----------------------------------------------------------------------------

    def globals(self, pose: Pose) -> tuple[list[tuple], list[tuple]]:
        """World orientations (quaternions) and positions (model frame, m) of every joint, as
        lists of float tuples: forward kinematics in plain floating point, which for 13 joints
        is several times faster than numpy's per-call overhead."""
        local = [tuple(q) for q in pose.rots.tolist()]
        qw = [local[0]]
        pw = [tuple(pose.root.tolist())]
        parent, offset = self._parent_list, self._offset_list
        for i in range(1, len(local)):
            p = parent[i]
            o = qrot(qw[p], offset[i])
            pp = pw[p]
            pw.append((pp[0] + o[0], pp[1] + o[1], pp[2] + o[2]))
            qw.append(qmul(qw[p], local[i]))
        return qw, pw

    def parts(self, pose: Pose, globals_: tuple[list, list] | None = None) -> np.ndarray:
        """Positions (6, 3) of :data:`PARTS` (model frame, metres)."""
        qw, pw = globals_ if globals_ is not None else self.globals(pose)
        out = []
        for b, off in zip(self._pb_list, self._po_list):
            o = qrot(qw[b], off)
            out.append((pw[b][0] + o[0], pw[b][1] + o[1], pw[b][2] + o[2]))
        return np.array(out)

    def points(self, pose: Pose) -> np.ndarray:
        """Joint positions then part points (19, 3), model frame: what :attr:`bones` connects."""
        g = self.globals(pose)
        return np.vstack([np.array(g[1]), self.parts(pose, g)])

    # --- limits --------------------------------------------------------------------------------

    def hinge_angle(self, rots: np.ndarray, i: int) -> float:
        """Signed angle (radians) of hinge ``i`` about its axis."""
        q = rots[i]
        return 2.0 * math.atan2(float(q[1:] @ self.axis[i]), float(q[0]))

    def clamp(self, rots: np.ndarray, i: int) -> None:
        """Bring joint ``i`` of ``rots`` (in place) within its limit."""
        if i == 0:
            return
        if self.hinge[i]:
            a = self.hinge_angle(rots, i)
            a = (a + math.pi) % (2 * math.pi) - math.pi
            rots[i] = quat_from_axis_angle(self.axis[i],
                                           min(max(a, self.hinge_lo[i]), self.hinge_hi[i]))
            return
        q = rots[i] if rots[i, 0] >= 0 else -rots[i]
        angle = 2.0 * math.acos(min(1.0, float(q[0])))
        lim = self.limit[i]
        if angle > lim:
            v = q[1:] / max(float(np.linalg.norm(q[1:])), 1e-12)
            rots[i] = np.concatenate([[math.cos(lim / 2)], math.sin(lim / 2) * v])

    def clamp_many(self, rots: np.ndarray, idx: list[int]) -> None:
        """:meth:`clamp` for several joints at once (in place), vectorised."""
        key = tuple(idx)
        split = self._clamp_split.get(key)
        if split is None:  # hinge and ball joints of this set, with their axes and limits
            ids = np.asarray([i for i in idx if i > 0], dtype=int)
            h, b = ids[self.hinge[ids]], ids[~self.hinge[ids]]
            split = self._clamp_split[key] = (h, self.axis[h], self.hinge_lo[h], self.hinge_hi[h],
                                              b, self.limit[b])
        h, ax, lo, hi, b, lim = split
        if h.size:
            a = 2.0 * np.arctan2(np.einsum("ij,ij->i", rots[h, 1:], ax), rots[h, 0])
            a = np.clip((a + np.pi) % (2 * np.pi) - np.pi, lo, hi)
            rots[h, 0] = np.cos(a / 2)
            rots[h, 1:] = np.sin(a / 2)[:, None] * ax
        if b.size:
            q = rots[b]
            angle = 2.0 * np.arccos(np.minimum(1.0, np.abs(q[:, 0])))
            over = angle > lim
            if over.any():
                q = q[over] * np.where(q[over, :1] < 0, -1.0, 1.0)
                v = q[:, 1:]
                v = v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-12)
                half = lim[over] / 2
                rots[b[over]] = np.concatenate([np.cos(half)[:, None], np.sin(half)[:, None] * v],
                                               axis=1)

    def violations(self, rots: np.ndarray, tol: float = 1e-6) -> list[str]:
        """Names of joints outside their limits (radians tolerance ``tol``)."""
        bad = []
        for i in range(1, len(self.names)):
            if self.hinge[i]:
                q = rots[i]
                off_axis = np.linalg.norm(q[1:] - (q[1:] @ self.axis[i]) * self.axis[i])
                a = self.hinge_angle(rots, i)
                a = (a + math.pi) % (2 * math.pi) - math.pi
                if off_axis > 1e-3 or a < self.hinge_lo[i] - tol or a > self.hinge_hi[i] + tol:
                    bad.append(self.names[i])
            else:
                w = abs(float(rots[i, 0]) / max(float(np.linalg.norm(rots[i])), 1e-12))
                if 2.0 * math.acos(min(1.0, w)) > self.limit[i] + tol:
                    bad.append(self.names[i])
        return bad

    # --- clips ---------------------------------------------------------------------------------

    def pose_from_values(self, clip: Clip, values: np.ndarray) -> Pose:
        """A pose from one sampled DeepMimic humanoid vector (channels named by URDF joints)."""
        root = np.array([values[clip.slices["root_x"]][0], values[clip.slices["root_y"]][0],
                         values[clip.slices["root_z"]][0]])
        rots = np.empty((len(self.names), 4))
        rots[0] = values[clip.slices["root_rot"]]
        for i, n in enumerate(JOINTS, start=1):
            v = values[clip.slices[n]]
            rots[i] = quat_from_axis_angle(self.axis[i], float(v[0])) if self.hinge[i] else v
        rots = quat_normalize(rots)
        for i in range(1, len(self.names)):
            self.clamp(rots, i)
        return Pose(root, rots)


def yaw_of(q: np.ndarray) -> float:
    """Heading (radians about the vertical y axis) of a pelvis quaternion: where its x axis
    points."""
    fwd = quat_to_matrix(q)[:, 0]
    return math.atan2(-float(fwd[2]), float(fwd[0]))


# Elevations a view may be set to (degrees): at +-90 the camera looks straight down or up the
# character's vertical axis, where azimuth no longer turns the view and the screen's up flips.
VIEW_ELEVATION_DEG = (-89.0, 89.0)


class Camera:
    """Orthographic virtual camera at ``azimuth``/``elevation`` (degrees) around the character.

    ``eye`` is the viewing direction (camera to character, model frame); ``right`` and ``up`` span
    the screen. The screen is laid on the table at ``scale`` table metres per character metre with
    the model origin (ground under the pelvis at rest) at ``origin`` (table metres).
    """

    def __init__(self, azimuth: float = 0.0, elevation: float = 15.0, scale: float = 1.0,
                 origin: Sequence[float] = (0.0, 0.0)) -> None:
        self.azimuth, self.elevation = float(azimuth), float(elevation)
        self.scale = float(scale)
        self.origin = np.asarray(origin, dtype=float)
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        cam = np.array([math.cos(el) * math.cos(az), math.sin(el), math.cos(el) * math.sin(az)])
        self.eye = -cam
        right = np.cross(self.eye, [0.0, 1.0, 0.0])
        # looking straight down: screen up is the character's forward
        if np.linalg.norm(right) < 1e-9:
            right = np.array([0.0, 0.0, -1.0]) if el > 0 else np.array([0.0, 0.0, 1.0])
        self.right = right / np.linalg.norm(right)
        self.up = np.cross(self.right, self.eye)
        self.matrix = np.stack([self.right, self.up])

    def turned(self, d_azimuth: float, d_elevation: float) -> "Camera":
        """This camera turned by the given degrees (elevation kept within -10..89)."""
        el = min(max(self.elevation + d_elevation, -10.0), 89.0)
        return Camera((self.azimuth + d_azimuth) % 360.0, el, self.scale, self.origin)

    def screen(self, points: np.ndarray) -> np.ndarray:
        """Screen points (..., 2; character metres) of model points (..., 3)."""
        return np.asarray(points, dtype=float) @ self.matrix.T

    def table(self, points: np.ndarray) -> np.ndarray:
        """Table points (..., 2; metres) of model points (..., 3)."""
        return self.screen(points) * self.scale + self.origin

    def to_screen(self, table_xy: np.ndarray) -> np.ndarray:
        """Screen points (character metres) of table points (metres)."""
        return (np.asarray(table_xy, dtype=float) - self.origin) / self.scale

    def ray_point(self, screen_xy: np.ndarray, near: np.ndarray) -> np.ndarray:
        """The point of a touch's half-line (screen point ``screen_xy``) closest to ``near``
        (3,)."""
        s = np.asarray(screen_xy, dtype=float)
        depth = float(np.asarray(near) @ self.eye)
        return s[0] * self.right + s[1] * self.up + depth * self.eye

    def angle_to_eye(self, vector: np.ndarray) -> float:
        """Acute angle (degrees) between a direction (model frame) and the viewing line."""
        v = np.asarray(vector, dtype=float)
        n = float(np.linalg.norm(v))
        if n < 1e-12:
            return 0.0
        return math.degrees(math.acos(min(1.0, abs(float(v @ self.eye)) / n)))
