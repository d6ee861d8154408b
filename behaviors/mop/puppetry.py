"""Characters played at the performer's progress (MOP 3.1.3 and 3.3), and the designer's takes.

A rig turns a motion clip at some progress into 2-D points (figure units, "up" along the
character's heading, see :func:`behaviors.motion.skeleton.place`):

- :class:`HumanoidRig`: a URDF skeleton driven by a DeepMimic-style clip (quaternion joints),
  by forward kinematics and a projection;
- :class:`PlanarRig`: a :class:`Skeleton2D` driven by 2-D joint angles named after its bones;
- :class:`FaceRig`: a :class:`FaceModel` driven by blendshape weights;
- :class:`~behaviors.mop.sprites.SpriteRig`: a vector sprite sheet whose frames a clip's
  ``frame`` channel picks (:mod:`behaviors.mop.sprites`);
- :class:`HybridRig`: a body and a face driven together (skeletal and blendshape channels).

:class:`Puppet` is one character: its actions (name -> clip, time warp), fed each tick with the
follower states of the performers bound to it. It shows the motion of the most probable valid
action at that action's progress (time alignment: action progress -> motion progress), cross-fades
for ``blend_s`` seconds when the action changes, holds the last pose for ``hold_s`` seconds when
nothing matches (or the most probable action is below ``min_probability``), then eases back to
the rest pose with time constant ``rest_s``.

The paper shows motions as they are, without interpolation. Every frame of an action here is
its motion at the followed progress; only where the driving action changes does the cross-fade
blend the pose shown with the new action's, because without it the figure leaps: on the example
installation's back-to-back sequences (``bench/mop_blend.py``: 18 switches) the largest
per-frame move of a point in the 0.25 s after a switch is 157 mm (dancer), 182 mm (salamander)
and 20 mm (face) with ``blend_s`` 0, against 55, 36 and 2.7 mm with 0.2 s, where within one
action the 99th percentile is 57, 29 and 2.5 mm (largest 83, 65, 2.8 mm): the 0.2 s fade brings
a switch down to the motions' own frame-to-frame moves. ``hold_s`` and ``rest_s`` shape only
the time no action drives (the last pose held, then eased to rest), not any action's motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol, Sequence

import numpy as np

from behaviors.motion.clips import Clip, ClipError, TimeWarp
from behaviors.motion.deepmimic import humanoid_pose
from behaviors.mop.creatures import FaceModel
from behaviors.mop.pose_tables import figure_key, shared_table
from behaviors.motion.skeleton import ProjectedFigure, Skeleton2D, place
from tabletop.frames import CharacterState


class Rig(Protocol):
    """Turns clip poses into figure points (N x 2, y along the heading)."""

    kind: str
    bones: tuple[tuple[int, int], ...]

    def check(self, clip: Clip) -> None: ...

    def pose(self, clip: Clip, progress: float) -> np.ndarray: ...

    def rest(self) -> np.ndarray: ...


class HumanoidRig:
    """A URDF figure; clip channels are named after its joints (DeepMimic layout). The root stays
    above the anchor unless ``travel`` (then it moves by its offset from the clip's start)."""

    kind = "skeleton"

    def __init__(self, figure: ProjectedFigure, travel: bool = False) -> None:
        self.figure = figure
        self.travel = bool(travel)
        self.bones = figure.bones
        self._joints = set(figure.skeleton.joint_names)
        self._cache: dict[int, tuple[Clip, np.ndarray]] = {}
        self.cache_hz = 120.0

    def check(self, clip: Clip) -> None:
        needed = {"root_x", "root_y", "root_z", "root_rot"}
        missing = needed - set(clip.names)
        if missing or not (set(clip.names) & self._joints):
            raise ClipError(f"clip {clip.name!r} does not drive skeleton "
                            f"{self.figure.skeleton.name!r}: it needs root_x, root_y, root_z, "
                            "root_rot and channels named after the skeleton's joints")
        self._table(clip)     # computed now (at build, or when the designer assigns it)

    def pose(self, clip: Clip, progress: float) -> np.ndarray:
        """Figure points at ``progress``, linear between poses computed once per clip (full
        kinematics) at ``cache_hz`` steps of the clip's time: within 1% of the figure's height of
        :meth:`exact_pose` even for the fast DeepMimic clips."""
        keys = self._table(clip)
        p = float(progress)
        p = 0.0 if p != p else min(max(p, 0.0), 1.0)
        x = p * (len(keys) - 1)
        i = min(int(x), len(keys) - 2)
        f = x - i
        return keys[i] + f * (keys[i + 1] - keys[i])

    def _table(self, clip: Clip) -> np.ndarray:
        entry = self._cache.get(id(clip))
        if entry is None or entry[0] is not clip:
            n = max(len(clip.times), int(math.ceil(clip.duration * self.cache_hz))) + 1
            key = figure_key(self.figure, self.travel, self.cache_hz)
            entry = (clip, shared_table(key, clip,
                                        lambda: self.exact_poses(clip, np.linspace(0, 1, n))))
            self._cache[id(clip)] = entry
        return entry[1]

    def exact_pose(self, clip: Clip, progress: float) -> np.ndarray:
        """Figure points of the clip's pose at ``progress`` (slerped joints, full kinematics)."""
        root, root_rot, rotations = humanoid_pose(clip, clip.sample(progress), self._joints)
        origin = None
        if self.travel:
            v0 = clip.values[0]
            origin = [v0[clip.slices["root_x"]][0], v0[clip.slices["root_y"]][0],
                      v0[clip.slices["root_z"]][0]]
        return self.figure.points(root, root_rot, rotations, self.travel, origin)

    def exact_poses(self, clip: Clip, progress: np.ndarray) -> np.ndarray:
        """:meth:`exact_pose` at every progress (M,) at once (M x N x 2 figure points), within
        4.4e-16 of it: examples/mop.yaml's engine builds in 0.05 CPU s instead of 0.31."""
        values = clip.sample_many(progress)
        cols = [clip.slices[k].start for k in ("root_x", "root_y", "root_z")]
        rotations = {n: values[:, clip.slices[n]] for n in self._joints if n in clip.slices}
        origin = clip.values[0, cols] if self.travel else None
        root = values[:, cols]
        return self.figure.points_many(root, values[:, clip.slices["root_rot"]], rotations,
                                       self.travel, origin)

    def rest(self) -> np.ndarray:
        return self.figure.rest_points()


def _forward_to_up(p: np.ndarray) -> np.ndarray:
    """Character-frame points (x forward, y left) as figure points (y along the heading)."""
    return np.stack([-p[:, 1], p[:, 0]], axis=1)


class PlanarRig:
    """A planar skeleton seen from above; clip channels are joint angles named after bones."""

    kind = "creature"

    def __init__(self, skeleton: Skeleton2D) -> None:
        self.skeleton = skeleton
        self.bones = skeleton.bones
        self._index = {n: i for i, n in enumerate(skeleton.names)}

    def check(self, clip: Clip) -> None:
        if not any(n in self._index for n in clip.names):
            raise ClipError(f"clip {clip.name!r} has no channel named after a bone of the "
                            f"creature ({', '.join(self.skeleton.names)})")

    def pose(self, clip: Clip, progress: float) -> np.ndarray:
        bones, values = clip.driven(self.skeleton.names, progress)
        angles = np.zeros(len(self.skeleton.names))
        angles[bones] = values
        return _forward_to_up(self.skeleton.forward(angles))

    def rest(self) -> np.ndarray:
        return _forward_to_up(self.skeleton.forward())


class FaceRig:
    """A face; clip channels are blendshape weights named after its blendshapes."""

    kind = "face"

    def __init__(self, face: FaceModel) -> None:
        self.face = face
        self.bones = face.bones
        self._index = {n: i for i, n in enumerate(face.BLENDSHAPES)}

    def check(self, clip: Clip) -> None:
        if not any(n in self._index for n in clip.names):
            raise ClipError(f"clip {clip.name!r} has no channel named after a blendshape "
                            f"({', '.join(self.face.BLENDSHAPES)})")

    def pose(self, clip: Clip, progress: float) -> np.ndarray:
        shapes, values = clip.driven(self.face.BLENDSHAPES, progress)
        w = np.zeros(len(self._index))
        w[shapes] = values
        return self.face.points(w)

    def rest(self) -> np.ndarray:
        return self.face.neutral.copy()


class HybridRig:
    """A body rig and a face driven together by one clip (MOP section 3's hybrid characters):
    skeletal channels pose the body, blendshape channels the face, which rides on the body's
    point ``head`` (scaled by ``face_size`` figure units, its chin along the heading).

    The face is turned half round on the body: seen from above, an animal's mouth is at its
    snout and its eyes behind it. Upright along the heading (brows at the snout, mouth at the
    neck), the gecko read as a face lying on its back with its chin in the body.

    With ``neck`` (a humanoid seen from the side), the face stands upright on the body instead:
    its chin on the point ``neck``, its up along neck -> ``head``, so it turns with the head
    (a cartwheel turns it over) and is not left upright beside a body upside down."""

    kind = "hybrid"

    def __init__(self, body: PlanarRig | HumanoidRig, face: FaceRig, head: int,
                 face_size: float = 0.35, neck: int | None = None) -> None:
        self.body, self.face, self.head, self.face_size = body, face, int(head), float(face_size)
        self.neck = None if neck is None else int(neck)
        n = len(body.rest())
        self.bones = tuple(body.bones) + tuple((a + n, b + n) for a, b in face.bones)

    def check(self, clip: Clip) -> None:
        self.body.check(clip)
        self.face.check(clip)

    def _join(self, body: np.ndarray, face: np.ndarray) -> np.ndarray:
        if self.neck is None:
            return np.vstack([body, body[self.head] - self.face_size * face])
        up = body[self.head] - body[self.neck]
        n = float(np.hypot(up[0], up[1]))
        ux, uy = (up / n).tolist() if n > 1e-9 else (0.0, 1.0)
        turn = np.array([[uy, -ux], [ux, uy]])    # face x, y (rows) -> figure units
        chin_up = face + np.array([0.0, 0.5])     # (the face's chin is at y = -0.5)
        return np.vstack([body, body[self.neck] + self.face_size * chin_up @ turn])

    def pose(self, clip: Clip, progress: float) -> np.ndarray:
        return self._join(self.body.pose(clip, progress), self.face.pose(clip, progress))

    def rest(self) -> np.ndarray:
        return self._join(self.body.rest(), self.face.rest())


@dataclass
class Action:
    """An action of a character: the motion it plays and the map from action to motion progress."""

    name: str
    clip: Clip
    warp: TimeWarp = field(default_factory=TimeWarp)


@dataclass(frozen=True)
class Vote:
    """One follower's view of one action: its probability, progress, and whether it is valid."""

    action: str
    probability: float
    progress: float
    valid: bool
    loglik: float = 0.0
    hint: bool = False    # among the performer's likeliest actions right now (early feedback)


class Puppet:
    """One character: plays the motion of the performed action at the action's progress.

    ``size``: figure units -> metres (a humanoid's standing height, a creature's length, a face's
    height); ``x, y, heading``: where it stands on the table (metres, radians).
    """

    def __init__(self, name: str, rig: Rig, actions: Sequence[Action], x: float, y: float,
                 heading: float, size: float, color: tuple[int, int, int] = (240, 170, 60),
                 blend_s: float = 0.2, hold_s: float = 0.5, rest_s: float = 0.4,
                 min_probability: float = 0.5) -> None:
        self.name, self.rig = name, rig
        self.actions: dict[str, Action] = {}
        for a in actions:
            self.add_action(a)
        self.x, self.y, self.heading, self.size, self.color = x, y, heading, size, color
        self.blend_s, self.hold_s, self.rest_s = blend_s, hold_s, rest_s
        self.min_probability = min_probability
        self._rest = rig.rest()
        self.reset()

    def add_action(self, action: Action) -> None:
        """Add (or replace) an action; its clip must drive this rig."""
        self.rig.check(action.clip)
        self.actions[action.name] = action

    def remove_action(self, name: str) -> None:
        self.actions.pop(name, None)

    def reset(self) -> None:
        self._shown = self._rest.copy()
        self._from = self._rest.copy()
        self._fade_until = -math.inf
        self._fade_start = -math.inf
        self._action: str | None = None
        self._progress: float | None = None
        self._last_valid_t = -math.inf
        self._t: float | None = None
        self._seen: dict[str, float] = {}
        self._moved: dict[str, float] = {}
        self._poses: dict[str, tuple] = {}    # action name -> (action, progress, pose)
        self._placed: list[tuple | None] = [None, None]   # (figure, x, y, heading, size, points)

    def _pose(self, action: Action, progress: float) -> np.ndarray:
        """The rig's figure points of ``action`` at its ``progress``, kept while both stay: a
        30 Hz sample's votes drive two 60 Hz frames. With :meth:`_place`: the example
        installation's frame (MopStage.step) 7.5% less CPU, every point the same to the bit."""
        kept = self._poses.get(action.name)
        if kept is None or kept[0] is not action or kept[1] != progress:
            kept = (action, progress, self.rig.pose(action.clip, float(action.warp(progress))))
            self._poses[action.name] = kept
        return kept[2]

    def _place(self, figure: np.ndarray, slot: int) -> np.ndarray:
        """:func:`place` of ``figure`` (the pose shown: slot 0, the hint's: 1), kept while the
        same array stands at the same place (a pose held, or a sample's second frame)."""
        kept, at = self._placed[slot], (self.x, self.y, self.heading, self.size)
        if kept is None or kept[0] is not figure or kept[1:5] != at:
            kept = (figure, *at, place(figure, *at))
            self._placed[slot] = kept
        return kept[5]

    def choose(self, votes: Sequence[Vote]) -> Vote | None:
        """The vote to show among valid votes for known actions at least ``min_probability``
        probable (an ambiguous start shows nothing): the one whose progress moved most recently
        (with several performers, the one performing now), then the most probable; else None."""
        best, best_key = None, None
        for v in votes:
            if v.valid and v.action in self.actions and v.probability >= self.min_probability:
                key = (self._moved.get(v.action, -math.inf), v.probability)
                if best_key is None or key > best_key:
                    best, best_key = v, key
        return best

    def update(self, t: float, votes: Sequence[Vote], label: str = "", hold: bool = True
               ) -> CharacterState:
        """The character at time ``t`` (seconds) given every bound follower's votes. Without a
        valid vote it holds its last pose ``hold_s`` seconds, still naming its action, then eases
        to rest; ``hold`` False eases to rest at once and names no action (a take recording)."""
        dt = 0.0 if self._t is None else max(0.0, t - self._t)
        self._t = t
        for v in votes:
            seen = self._seen.get(v.action)
            if seen is None or abs(v.progress - seen) > 0.005:
                self._moved[v.action] = t if seen is not None else -math.inf
                self._seen[v.action] = v.progress
        vote = self.choose(votes)
        valid = vote is not None
        if vote is not None:
            action = self.actions[vote.action]
            target = self._pose(action, vote.progress)
            if vote.action != self._action:
                self._from = self._shown.copy()
                self._fade_start, self._fade_until = t, t + self.blend_s
                self._action = vote.action
            self._progress = vote.progress
            self._last_valid_t = t
            if t < self._fade_until and self.blend_s > 0:
                w = (t - self._fade_start) / self.blend_s
                w = w * w * (3 - 2 * w)
                target = (1 - w) * self._from + w * target
            self._shown = target
        elif not hold or t - self._last_valid_t > self.hold_s:
            k = 1.0 - math.exp(-dt / self.rest_s) if self.rest_s > 0 else 1.0
            self._shown = self._shown + k * (self._rest - self._shown)
            self._action = None
        pts = self._place(self._shown, 0)
        hints = tuple(sorted(((v.action, v.probability, v.progress) for v in votes
                              if v.hint and v.action in self.actions and not v.valid),
                             key=lambda h: -h[1]))
        ghost = None
        if hints and not valid:
            # early feedback: the likeliest action's pose at its progress, drawn faintly
            ghost = self._place(self._pose(self.actions[hints[0][0]], hints[0][2]), 1)
        if not label:
            label = (f"{vote.action} {vote.progress:4.2f} p={vote.probability:.2f}" if vote
                     else "no action")
        return CharacterState(self.name, self.x, self.y, self.heading, kind=self.rig.kind,
                              size=self.size, color=self.color, points=pts, bones=self.rig.bones,
                              progress=self._progress if valid else None,
                              action=vote.action if vote else self._action, valid=valid,
                              label=label, hints=hints, hint_points=ghost)
