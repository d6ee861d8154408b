"""Skeletons for characters: a 3-D URDF skeleton with forward kinematics and a projection onto
the table, and a planar skeleton driven by 2-D joint angles.

3-D: :func:`load_urdf` reads links and joints (fixed, spherical, revolute, continuous) from a URDF
file, such as ``pybullet_data/humanoid/humanoid.urdf``. :meth:`UrdfSkeleton.forward` places every
joint in model space (the model's own units and axes) from a root position, a root rotation and
each joint's rotation (a quaternion w-first for ball joints, an angle in radians for hinges).
:class:`Projection` turns those 3-D points into a flat figure on the table: an orthographic view
from a chosen side, laid on the table with the figure's "up" along the character's heading and
scaled so the rest pose is ``size`` metres tall.

2-D: :class:`Skeleton2D` is a tree of bones, each a length and a rest angle relative to its
parent; joint angles (radians) add to the rest angles. Its points are in the character's own
frame (metres, x forward), placed on the table by :func:`place`.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from behaviors.motion.clips import quat_to_matrix
from tabletop.frames import InputError


class SkeletonError(InputError):
    """A skeleton file is missing or malformed; the message names the file."""


@dataclass(frozen=True)
class Joint3D:
    """A URDF joint: parent and child links, its origin in the parent link frame, its type and
    hinge axis (unit, in the joint frame)."""

    name: str
    type: str
    parent: str
    child: str
    xyz: np.ndarray
    rot: np.ndarray
    axis: np.ndarray


def _rpy_matrix(r: float, p: float, y: float) -> np.ndarray:
    """URDF fixed-axis roll, pitch, yaw: R = Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp = math.cos(r), math.sin(r), math.cos(p), math.sin(p)
    cy, sy = math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def _floats(text: str | None, n: int, what: str, file: str) -> np.ndarray:
    try:
        vals = [float(v) for v in (text or "").split()]
    except ValueError:
        raise SkeletonError(f"{file}: {what}: {text!r} is not {n} numbers") from None
    if len(vals) != n:
        raise SkeletonError(f"{file}: {what}: {text!r} is not {n} numbers")
    return np.array(vals)


class UrdfSkeleton:
    """Links and joints of a URDF, ordered parents first; points are the joint positions plus a
    tip for each leaf link that has a visual shape (the head, the feet)."""

    def __init__(self, name: str, root_link: str, joints: Sequence[Joint3D],
                 tips: Mapping[str, np.ndarray]) -> None:
        self.name = name
        self.root_link = root_link
        self.joints = tuple(joints)
        self.joint_names = tuple(j.name for j in self.joints)
        self.link_names = (root_link,) + tuple(j.child for j in self.joints)
        link_index = {n: i for i, n in enumerate(self.link_names)}
        self._parent_index = [link_index[j.parent] for j in self.joints]
        self.tips = {k: np.asarray(v, dtype=float) for k, v in tips.items()}
        self.point_names = self.link_names + tuple(f"{k}_tip" for k in self.tips)
        bones: list[tuple[int, int]] = []
        for i, j in enumerate(self.joints):
            if not np.allclose(j.xyz, 0.0):
                bones.append((self._parent_index[i], i + 1))
        for k, name_ in enumerate(self.tips):
            bones.append((link_index[name_], len(self.link_names) + k))
        self.bones = tuple(b for b in bones if b[0] != b[1])
        self._tip_links = [link_index[n] for n in self.tips]
        self._ball = [i for i, j in enumerate(self.joints) if j.type == "spherical"]
        self._hinge = [i for i, j in enumerate(self.joints) if j.type in ("revolute", "continuous")]
        cross = np.array([[[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]]
                          for a in (self.joints[i].axis for i in self._hinge)]).reshape(-1, 3, 3)
        self._hinge_k, self._hinge_k2 = cross, cross @ cross
        # joints grouped by depth, so forward kinematics runs one batched step per level
        depth = [0] * len(self.link_names)
        for i in range(len(self.joints)):
            depth[i + 1] = depth[self._parent_index[i]] + 1
        self._levels = []
        for d in range(1, max(depth) + 1):
            js = [i for i in range(len(self.joints)) if depth[i + 1] == d]
            fixed = np.array([self.joints[i].rot for i in js])
            self._levels.append((np.array(js), np.array([self._parent_index[i] for i in js]),
                                 np.array(js) + 1, None if np.allclose(fixed, np.eye(3)) else fixed,
                                 np.array([self.joints[i].xyz for i in js])[:, :, None]))
        self._tip_offsets = np.array([self.tips[n] for n in self.tips]).reshape(-1, 3)

    def forward(self, root_pos: Sequence[float] = (0.0, 0.0, 0.0),
                root_rot: Sequence[float] = (1.0, 0.0, 0.0, 0.0),
                rotations: Mapping[str, np.ndarray | float] | None = None) -> np.ndarray:
        """Model-space positions (N x 3) of every point, in :attr:`point_names` order.

        ``rotations``: joint name -> quaternion (w, x, y, z) for spherical joints, angle
        (radians, about the joint axis) for revolute and continuous joints; missing joints are at
        rest; fixed joints ignore it.
        """
        rotations = rotations or {}
        n_links = len(self.link_names)
        pos = np.empty((n_links, 3))
        rot = np.empty((n_links, 3, 3))
        pos[0] = np.asarray(root_pos, dtype=float)
        # each joint's own rotation, vectorised: ball joints from quaternions, hinges by Rodrigues
        local = np.broadcast_to(np.eye(3), (len(self.joints), 3, 3)).copy()
        balls = [i for i in self._ball if self.joints[i].name in rotations]
        quats = [np.asarray(root_rot, dtype=float).reshape(4)]
        quats += [np.asarray(rotations[self.joints[i].name], dtype=float).reshape(4) for i in balls]
        mats = quat_to_matrix(np.array(quats))
        rot[0] = mats[0]
        if balls:
            local[balls] = mats[1:]
        hinges = [k for k, i in enumerate(self._hinge) if self.joints[i].name in rotations]
        if hinges:
            idx = [self._hinge[k] for k in hinges]
            theta = np.array([float(np.asarray(rotations[self.joints[i].name]).reshape(-1)[0])
                              for i in idx])
            local[idx] = (np.eye(3) + np.sin(theta)[:, None, None] * self._hinge_k[hinges]
                          + (1 - np.cos(theta))[:, None, None] * self._hinge_k2[hinges])
        for joints, parents, children, fixed, xyz in self._levels:
            rp = rot[parents]
            pos[children] = pos[parents] + (rp @ xyz)[:, :, 0]
            rot[children] = rp @ local[joints] if fixed is None else rp @ fixed @ local[joints]
        if not self._tip_links:
            return pos
        tips = (rot[self._tip_links] @ self._tip_offsets[:, :, None])[:, :, 0] \
            + pos[self._tip_links]
        return np.vstack([pos, tips])


    def forward_many(self, root_pos: np.ndarray, root_rot: np.ndarray,
                     rotations: Mapping[str, np.ndarray]) -> np.ndarray:
        """:meth:`forward` of M poses at once (M x N x 3): root positions (M x 3), root
        quaternions (M x 4), joint name -> quaternions (M x 4) or hinge angles (M or M x 1,
        radians). Every sample's arithmetic is :meth:`forward`'s, elementwise along M."""
        root_pos = np.asarray(root_pos, dtype=float).reshape(-1, 3)
        m, n_links = len(root_pos), len(self.link_names)
        pos = np.empty((m, n_links, 3))
        rot = np.empty((m, n_links, 3, 3))
        pos[:, 0] = root_pos
        local = np.broadcast_to(np.eye(3), (m, len(self.joints), 3, 3)).copy()
        balls = [i for i in self._ball if self.joints[i].name in rotations]
        quats = [np.asarray(root_rot, dtype=float).reshape(m, 4)]
        quats += [np.asarray(rotations[self.joints[i].name], dtype=float).reshape(m, 4)
                  for i in balls]
        mats = quat_to_matrix(np.stack(quats, axis=1))
        rot[:, 0] = mats[:, 0]
        if balls:
            local[:, balls] = mats[:, 1:]
        hinges = [k for k, i in enumerate(self._hinge) if self.joints[i].name in rotations]
        if hinges:
            idx = [self._hinge[k] for k in hinges]
            theta = np.stack([np.asarray(rotations[self.joints[i].name], dtype=float)
                              .reshape(m, -1)[:, 0] for i in idx], axis=1)
            local[:, idx] = (np.eye(3) + np.sin(theta)[..., None, None] * self._hinge_k[hinges]
                             + (1 - np.cos(theta))[..., None, None] * self._hinge_k2[hinges])
        for joints, parents, children, fixed, xyz in self._levels:
            rp = rot[:, parents]
            pos[:, children] = pos[:, parents] + (rp @ xyz)[..., 0]
            rot[:, children] = (rp @ local[:, joints] if fixed is None
                                else rp @ fixed @ local[:, joints])
        if not self._tip_links:
            return pos
        tips = (rot[:, self._tip_links] @ self._tip_offsets[:, :, None])[..., 0] \
            + pos[:, self._tip_links]
        return np.concatenate([pos, tips], axis=1)

def load_urdf(path: str | Path) -> UrdfSkeleton:
    """Read a URDF file's kinematic tree. Raises :class:`SkeletonError` naming the file."""
    p = Path(path)
    file = str(p)
    try:
        # Some exporters (pybullet's humanoid.urdf among them) end the file with a NUL byte.
        root = ET.fromstring(p.read_bytes().rstrip(b"\x00 \t\r\n"))
    except FileNotFoundError:
        raise SkeletonError(f"{file}: skeleton file not found") from None
    except (OSError, ET.ParseError) as exc:
        raise SkeletonError(f"{file}: cannot read URDF: {exc}") from None
    if root.tag != "robot":
        raise SkeletonError(f"{file}: not a URDF file (top element is <{root.tag}>, not <robot>)")
    links = {ln.get("name"): ln for ln in root.findall("link")}
    raw: list[Joint3D] = []
    for je in root.findall("joint"):
        name = je.get("name") or "?"
        jtype = je.get("type") or "fixed"
        if jtype not in ("fixed", "spherical", "revolute", "continuous"):
            raise SkeletonError(f"{file}: joint {name!r} has type {jtype!r}; supported: fixed, "
                                "spherical, revolute, continuous")
        par, chi = je.find("parent"), je.find("child")
        if par is None or chi is None or par.get("link") not in links \
                or chi.get("link") not in links:
            raise SkeletonError(f"{file}: joint {name!r} needs a parent and a child link that "
                                "exist")
        org = je.find("origin")
        xyz = _floats(org.get("xyz", "0 0 0") if org is not None else "0 0 0", 3,
                      f"joint {name!r} origin xyz", file)
        rpy = _floats(org.get("rpy", "0 0 0") if org is not None else "0 0 0", 3,
                      f"joint {name!r} origin rpy", file)
        ax = je.find("axis")
        axis = _floats(ax.get("xyz") if ax is not None else "1 0 0", 3,
                       f"joint {name!r} axis", file)
        norm = float(np.linalg.norm(axis))
        if norm < 1e-12:
            raise SkeletonError(f"{file}: joint {name!r} has a zero axis")
        raw.append(Joint3D(name, jtype, par.get("link"), chi.get("link"), xyz,
                           _rpy_matrix(*rpy), axis / norm))
    if not raw:
        raise SkeletonError(f"{file}: no joints")
    children = {j.child for j in raw}
    roots = [n for n in links if n not in children]
    if len(roots) != 1:
        raise SkeletonError(f"{file}: expected one root link, found {len(roots)}: {roots}")
    ordered: list[Joint3D] = []
    placed = {roots[0]}
    pending = list(raw)
    while pending:
        ready = [j for j in pending if j.parent in placed]
        if not ready:
            raise SkeletonError(f"{file}: joints {[j.name for j in pending]} are not connected "
                                "to the root link")
        for j in ready:
            ordered.append(j)
            placed.add(j.child)
            pending.remove(j)
    parents = {j.parent for j in raw}
    tips: dict[str, np.ndarray] = {}
    for j in ordered:
        if j.child in parents:
            continue
        tip = _visual_tip(links[j.child])
        if tip is not None:
            tips[j.child] = tip
    return UrdfSkeleton(root.get("name") or p.stem, roots[0], ordered, tips)


def _visual_tip(link: ET.Element) -> np.ndarray | None:
    """The far end of a leaf link's visual (else collision) shape along its offset (top of a head,
    toe of a foot), or None when the shape sits on the joint."""
    vis = link.find("visual")
    if vis is None:
        vis = link.find("collision")
    if vis is None:
        return None
    org = vis.find("origin")
    try:
        c = np.array([float(v) for v in (org.get("xyz", "0 0 0") if org is not None
                                         else "0 0 0").split()])
    except ValueError:
        return None
    if c.shape != (3,) or np.linalg.norm(c) < 1e-9:
        return None
    k = int(np.argmax(np.abs(c)))
    geom = vis.find("geometry")
    half = 0.0
    if geom is not None:
        sphere, box = geom.find("sphere"), geom.find("box")
        try:
            if sphere is not None:
                half = float(sphere.get("radius", "0"))
            elif box is not None:
                half = float(box.get("size", "0 0 0").split()[k]) / 2
        except (ValueError, IndexError):
            half = 0.0
    tip = c.copy()
    tip[k] += math.copysign(half, c[k])
    return tip


# --- projection onto the table ------------------------------------------------------------------

class Projection:
    """An orthographic view of a model-space figure, giving 2-D points (figure units).

    ``up`` and ``forward`` are the model's vertical and facing axes (DeepMimic: y up, x forward).
    ``view_yaw`` (radians) turns the viewer about the vertical: 0 sees the figure from its side
    (forward is screen right), pi/2 from its front. ``elevation`` tilts the view down a little so
    depth shows. Screen x is to the right, screen y is up.
    """

    def __init__(self, up: Sequence[float] = (0, 1, 0), forward: Sequence[float] = (1, 0, 0),
                 view_yaw: float = 0.5, elevation: float = 0.25) -> None:
        u = np.asarray(up, dtype=float)
        f = np.asarray(forward, dtype=float)
        u = u / np.linalg.norm(u)
        f = f - u * (f @ u)
        if np.linalg.norm(f) < 1e-9:
            raise SkeletonError("projection: the forward axis must not be the up axis")
        f = f / np.linalg.norm(f)
        side = np.cross(u, f)
        cy, sy = math.cos(view_yaw), math.sin(view_yaw)
        right = cy * f + sy * side
        depth = np.cross(right, u)
        ce, se = math.cos(elevation), math.sin(elevation)
        self.matrix = np.stack([right, ce * u + se * depth])
        self.up = u

    def __call__(self, points3d: np.ndarray) -> np.ndarray:
        """2-D points (N x 2) of model points (N x 3)."""
        return np.asarray(points3d, dtype=float) @ self.matrix.T


def place(points2d: np.ndarray, x: float, y: float, heading: float, scale: float = 1.0,
          up_is_heading: bool = True) -> np.ndarray:
    """Table points (N x 2, metres) of figure points (N x 2): scaled by ``scale`` then turned so
    the figure's screen-up (``up_is_heading``) or its +x points along ``heading``, then moved to
    (x, y)."""
    p = np.asarray(points2d, dtype=float) * scale
    a = heading - math.pi / 2 if up_is_heading else heading
    c, s = math.cos(a), math.sin(a)
    out = np.empty_like(p)
    out[:, 0] = x + c * p[:, 0] - s * p[:, 1]
    out[:, 1] = y + s * p[:, 0] + c * p[:, 1]
    return out


# --- planar skeleton ----------------------------------------------------------------------------

class Skeleton2D:
    """A planar tree of bones. Point 0 is the root; bone i runs from point ``parents[i]`` to point
    i + 1, ``lengths[i]`` long (metres), at ``rest[i]`` radians relative to its parent bone (or to
    the root's facing for bones on the root) plus the joint angle i."""

    def __init__(self, names: Sequence[str], parents: Sequence[int], lengths: Sequence[float],
                 rest: Sequence[float]) -> None:
        self.names = tuple(names)
        self.parents = np.asarray(parents, dtype=int)
        self.lengths = np.asarray(lengths, dtype=float)
        self.rest = np.asarray(rest, dtype=float)
        n = len(self.names)
        if not (len(self.parents) == len(self.lengths) == len(self.rest) == n) or n == 0:
            raise SkeletonError("planar skeleton: names, parents, lengths and rest differ in "
                                "length")
        for i, p in enumerate(self.parents):
            if not 0 <= p <= i:
                raise SkeletonError(f"planar skeleton: bone {self.names[i]!r} has parent point "
                                    f"{p}; "
                                    "a bone must hang from the root or an earlier bone")
        self.bones = tuple((int(p), i + 1) for i, p in enumerate(self.parents))
        self._parents_list = self.parents.tolist()
        self._lengths_list = self.lengths.tolist()

    def forward(self, angles: np.ndarray | None = None) -> np.ndarray:
        """Points (N+1 x 2, metres, character frame: x forward) at joint ``angles`` (radians)."""
        a = (self.rest if angles is None else self.rest + np.asarray(angles, dtype=float)).tolist()
        xs, ys, direction = [0.0], [0.0], [0.0]
        for i, (p, length) in enumerate(zip(self._parents_list, self._lengths_list)):
            d = direction[p] + a[i]
            direction.append(d)
            xs.append(xs[p] + length * math.cos(d))
            ys.append(ys[p] + length * math.sin(d))
        return np.array([xs, ys]).T


class ProjectedFigure:
    """A 3-D skeleton seen through a :class:`Projection`, as 2-D points in units of its standing
    height: the floor at y = 0, the root above x = 0 (unless the root travels).

    ``root_scale`` converts clip root positions into skeleton units (DeepMimic clips are at a
    quarter of the URDF's size).
    """

    def __init__(self, skeleton: UrdfSkeleton, projection: Projection,
                 root_scale: float = 1.0) -> None:
        self.skeleton = skeleton
        self.projection = projection
        self.root_scale = float(root_scale)
        rest = projection(skeleton.forward())
        self.rest_height = float(rest[:, 1].max() - rest[:, 1].min())
        if not self.rest_height > 1e-9:
            raise SkeletonError(f"skeleton {skeleton.name!r}: its rest pose has no height")
        self._rest_floor = float(rest[:, 1].min())

    @property
    def bones(self) -> tuple[tuple[int, int], ...]:
        return self.skeleton.bones

    def rest_points(self) -> np.ndarray:
        """The rest pose standing on the floor (N x 2, heights)."""
        pts = self.projection(self.skeleton.forward())
        pts[:, 1] -= self._rest_floor
        return pts / self.rest_height

    def points(self, root_pos: Sequence[float], root_rot: Sequence[float],
               rotations: Mapping[str, np.ndarray | float], travel: bool = False,
               origin: Sequence[float] | None = None) -> np.ndarray:
        """2-D points (N x 2, standing heights) of a pose. Without ``travel`` the root stays
        above the origin (only its height moves, for jumps and crawls); with it, the root moves by
        its offset from ``origin`` (the clip's first root position)."""
        r = np.asarray(root_pos, dtype=float) * self.root_scale
        up = self.projection.up
        height = up * (r @ up)
        if travel:
            o = np.zeros(3) if origin is None else np.asarray(origin, dtype=float) * self.root_scale
            o = o - up * (o @ up)
            r = r - o
        else:
            r = height
        pts = self.projection(self.skeleton.forward(r, root_rot, rotations))
        return pts / self.rest_height

    def points_many(self, root_pos: np.ndarray, root_rot: np.ndarray,
                    rotations: Mapping[str, np.ndarray], travel: bool = False,
                    origin: Sequence[float] | None = None) -> np.ndarray:
        """:meth:`points` of M poses at once (M x N x 2): root positions (M x 3), root
        quaternions (M x 4), joint rotations as in :meth:`UrdfSkeleton.forward_many`."""
        r = np.asarray(root_pos, dtype=float).reshape(-1, 3) * self.root_scale
        up = self.projection.up
        if travel:
            o = np.zeros(3) if origin is None else np.asarray(origin, dtype=float) * self.root_scale
            o = o - up * (o @ up)
            r = r - o
        else:
            r = up * np.array([[row @ up] for row in r])
        pts = self.projection(self.skeleton.forward_many(r, root_rot, rotations))
        return pts / self.rest_height
