"""Touch-pose control of one character (paper 003, sections 3-6): the thin stateful engine.

Each :meth:`TouchPose.step` takes the fingers on the table (id -> table metres) at time t and:

1. picks, for every new finger, the nearest projected body part within ``reach`` (table metres),
   or nothing; two or more fingers on empty table turn the camera (azimuth with their common
   sideways motion, elevation with the up/down motion);
2. posing control: blends the posing model's samples for the touched parts' half-lines, corrects
   with CCD IK (at most 0.2 m), keeps planted feet where they stand; with no touch the posture
   stays; a touch on an action's primary part whose drag matches that action starts it;
3. action control: generalised time toward the synthesised time, stillness and automatic
   direction by segment; once the time comes within one frame's interval of the synthesised
   time, the synthesised posture itself is output, else the sample motions' posture at the
   time with the synthesis's motion weights (section 5); a finger resting where the action may
   stand holds the time and the posture (``action.REST_BAND``, ``action_control.REST_SPAN``);
   secondary touches by IK, unlimited
   (a held part stays fixed under its finger as the action moves); at the end
   back to posing where the action left the character (its position and heading become the
   posing base, within ``ROAM``), posing's target faded in from the action's (``HANDOVER_S``):
   :mod:`behaviors.touch_pose.action_control`;
4. tracking control: equations 2-4, then the physical effect (equations 5-7) on free segments,
   feet on the ground re-fixed by IK.

Everything is causal: the output at t depends only on fingers up to t.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Mapping

import numpy as np

from behaviors.touch_pose.action import EXCLUDE_DEG, ActionClock, ActionModel
from behaviors.touch_pose.action_control import ActionControl, Handover
from behaviors.touch_pose.edge import TABLE_MARGIN, EdgeLift, EdgeOffset, EdgeSide
from behaviors.touch_pose.fingers import Finger, common_motion
from behaviors.touch_pose.humanoid import MODEL_TO_WORLD, PARTS, Camera, Pose, qrot
from behaviors.touch_pose.ik import CCD, limit_goal
from behaviors.touch_pose.latent import Blend, yaw_view
from behaviors.touch_pose.models import Models, load_or_build
from behaviors.touch_pose.samples import place
from behaviors.touch_pose.tracking import PhysicalEffect, Tracker, apply_effect, free_segments
from tabletop.frames import MAX_POSITION_M

#: Height (m) under which a foot counts as on the ground.
GROUND = 0.08
#: Camera turn per metre of two-finger drag on empty table (degrees).
TURN_DEG_PER_M = 300.0
#: Parts drawn within this fraction of ``reach`` of the nearest to a finger overlap it: the
#: finger takes the one in front.
OVERLAP = 0.25
#: Seconds of each finger's path kept for recognising actions (a longer drag never matches).
PATH_S = 2.5


_MODELS: Models | None = None


def learned_models() -> Models:
    """The humanoid, posing model and action models (once per process: from the user's cache
    folder when learned before for the same inputs, else learned, a few seconds, and kept)."""
    global _MODELS
    if _MODELS is None:
        _MODELS = load_or_build()[0]
    return _MODELS


class TouchPose(ActionControl, EdgeOffset):
    """One touch-posed character on the table."""

    def __init__(self, table: tuple[float, float] = (1.2, 0.8), height: float = 0.3,
                 azimuth: float = 0.0, elevation: float = 15.0, reach: float = 0.04,
                 physics: bool = True, models: Models | None = None,
                 at: tuple[float, float] | None = None) -> None:
        self.m = models or learned_models()
        body = self.m.body
        self.body = body
        self.ccd = CCD(body)
        self.table = (float(table[0]), float(table[1]))
        self.centre = np.array(table, dtype=float) / 2.0 if at is None else np.array(at, float)
        pts = body.points(self.m.stand)
        self.stand_height = float(pts[:, 1].max())
        self.scale = float(height) / self.stand_height
        self.camera = self._camera(azimuth, elevation)
        self.reach = float(reach)
        self.base = np.zeros(2)
        self.yaw = 0.0
        self.target = self.m.stand.copy()
        self.tracker = Tracker(self.target)
        self.output = self.target.copy()
        self.effect = PhysicalEffect(len(body.names))
        self.physics = None
        if physics:
            from behaviors.touch_pose.physics import Physics
            self.physics = Physics(body)
        self.fingers: dict[int, Finger] = {}
        self.mode = "posing"
        self.clock: ActionClock | None = None
        self.action_blend: tuple[ActionModel, Blend] | None = None
        self.rest_pose: Pose | None = None
        self.action_base: tuple[np.ndarray, float] = (self.base, self.yaw)
        self.last_t: float | None = None
        self.recognising = True   # False while a designer records a take: drags only pose
        self._np = len(body.names)
        self._memo: dict[int, tuple[Pose, np.ndarray]] = {}
        # the ended action's last target, it moved to the base, and the faded-in part (0-1)
        self.handover: Handover | None = None
        self.edge = EdgeLift()   # the drawing's table-y offset near the top or bottom edge
        self.side = EdgeSide()   # its table-x offset near the left or right end

    # --- actions -------------------------------------------------------------------------------

    def add_action(self, action: ActionModel) -> None:
        """Add ``action`` (a designed one) to this character's actions, replacing one of its
        name (the learned models shared with other characters are left as they are)."""
        self.remove_action(action.name)
        self.m = dataclasses.replace(self.m, actions=[*self.m.actions, action])
        self._excluded_key = None

    def remove_action(self, name: str) -> None:
        """This character no longer knows the action ``name`` (one in play ends: posing)."""
        if self.mode == "action" and self.clock is not None and self.clock.action.name == name:
            self.mode, self.clock = "posing", None
        if any(a.name == name for a in self.m.actions):
            self.m = dataclasses.replace(self.m, actions=[a for a in self.m.actions
                                                          if a.name != name])
            self._excluded_key = None

    # --- view ----------------------------------------------------------------------------------

    def _camera(self, azimuth: float, elevation: float) -> Camera:
        """The camera drawing the standing figure's middle at ``centre``, moved just enough
        that the standing figure is drawn ``TABLE_MARGIN`` inside the table's edges (where it
        fits). ``at: [0.6, 0.1]`` (0.3 m tall, view 90,15) drew its feet at y = -0.041 m."""
        cam = Camera(azimuth, elevation, self.scale)
        mid = cam.screen(np.array([0.0, self.stand_height / 2, 0.0]))
        origin = self.centre - mid * self.scale
        drawn = cam.screen(self.body.points(self.m.stand)) * self.scale + origin
        lo, hi = drawn.min(axis=0), drawn.max(axis=0)
        room = np.array(self.table) - TABLE_MARGIN
        fits = hi - lo <= room - TABLE_MARGIN
        shift = np.where(lo < TABLE_MARGIN, TABLE_MARGIN - lo, np.minimum(room - hi, 0.0))
        return Camera(azimuth, elevation, self.scale, origin + np.where(fits, shift, 0.0))

    def excluded(self) -> set[str]:
        """Actions whose trajectory points within 45 degrees of the viewing line from here."""
        key = (self.camera.azimuth, self.camera.elevation, self.yaw)
        if getattr(self, "_excluded_key", None) != key:
            rot = _yaw_matrix(self.yaw)
            self._excluded = {a.name for a in self.m.actions
                              if self.camera.angle_to_eye(rot @ a.vector) < EXCLUDE_DEG}
            self._excluded_key = key
        return self._excluded

    def stroke_on_table(self, action: ActionModel) -> np.ndarray:
        """``action``'s stroke projected on the table from where its part stands now (n, 2;
        metres): the path a drag follows to start it."""
        view, _ = yaw_view(self.camera.matrix, self.base, self.yaw)
        part = self._np + PARTS.index(action.spec.part)
        start = self.camera.table(self._points(self.output)[part])
        return start + (action.stroke @ view.T) * self.scale

    def describe(self) -> dict:
        """The standing pose's parts and every action's projected stroke from where its part
        stands now, with the seconds it takes (DESIGN.md ``--describe``)."""
        parts = self.body.parts(place(self.m.stand, self.base, self.yaw))
        excluded = self.excluded()
        actions = []
        for a in self.m.actions:
            traj = self.stroke_on_table(a)
            # stroke_s: the seconds its trajectory takes at the action's pace, which a drag
            # must keep up with to start it (over duration_s, the whole clip's, none started)
            actions.append({"name": a.name, "part": a.spec.part, "duration_s": round(a.duration, 4),
                            "stroke_s": round(float(a.stroke_t[-1]), 4),
                            "excluded": a.name in excluded,
                            "trajectory": np.round(traj, 5).tolist()})
        return {"height_m": round(self.scale * self.stand_height, 6),
                "parts": {p: np.round(self.camera.table(parts[k]), 5).tolist()
                          for k, p in enumerate(PARTS)},
                "actions": actions}

    # --- stepping ------------------------------------------------------------------------------

    def step(self, t: float, touches: Mapping[int, tuple[float, float]],
             record: bool = True) -> dict | None:
        """Advance to time ``t`` (s) with fingers ``touches`` (id -> table x, y metres); the
        output record (see :meth:`frame`) unless ``record`` is False."""
        dt = 1.0 / 30.0 if self.last_t is None else min(max(t - self.last_t, 1e-4), 0.2)
        self.last_t = t
        # a source's broken touch (not a finite position, or beyond frames.MAX_POSITION_M: one
        # at 1e200 m made every later joint NaN) is no finger
        touches = {i: xy for i, xy in touches.items()
                   if abs(xy[0]) <= MAX_POSITION_M and abs(xy[1]) <= MAX_POSITION_M}
        self._fingers(t, touches)
        if self.mode == "posing":
            self._posing(dt)
        if self.mode == "action":
            self._action(dt)
        self.target = self._on_table(self.target)
        self.track(dt)
        self.edge.lift = self._edge_lift(t, dt)
        self.side.side = self._edge_side(t, dt)
        return self.frame(t) if record else None

    def track(self, dt: float) -> None:
        """Tracking control (section 6) of the current target for ``dt`` seconds."""
        held = {f.part for f in self.fingers.values() if f.part is not None}
        out = self.tracker.step(self.target, dt)
        grounded = self._grounded(self.target, self._points(self.target)[self._np:])
        if self.physics is not None:
            resets = self.physics.resets
            sim = self.physics.step(out, dt)
            if self.physics.resets != resets:
                self.effect.reset()  # the body was put back: its jump is no physical effect
            self.effect.update(sim, out, dt)
            free = free_segments(held, grounded)
            shaken = apply_effect(self.body, out, self.effect, free)
            if "torso" in free and grounded:
                parts = self.body.parts(out)
                shaken = self.ccd.solve(shaken, {p: parts[PARTS.index(p)] for p in grounded})
            out = shaken
        self.output = out

    def turn(self, d_azimuth: float, d_elevation: float) -> None:
        """Turn the virtual camera (degrees); drags in progress restart in the new view."""
        cam = self.camera.turned(d_azimuth, d_elevation)
        self.camera = self._camera(cam.azimuth, cam.elevation)
        for f in self.fingers.values():
            f.restart(self.camera.to_screen(f.table))

    def table_points(self) -> np.ndarray:
        """The output posture's joints and parts projected on the table (19, 2; metres), in
        the order :attr:`Humanoid.bones` indexes, drawn offset near the table's edge."""
        return self._drawn(self._points(self.output))

    def _drawn(self, points: np.ndarray) -> np.ndarray:
        """Table points (m) of model ``points`` as drawn: with the edge offsets (table x, y)."""
        xy = self.camera.table(points)
        if self.edge.lift != 0.0 or self.side.side != 0.0:
            xy = xy + np.array([self.side.side, self.edge.lift])
        return xy

    def head_facing(self) -> tuple[float, float, float]:
        """Where the output posture's head turns (its forward, the model's x, about the
        vertical) as the camera sees it: (table x, table y, toward the viewer), a unit vector
        (the viewpoint against the head, as the paper's eye vector against an action's). Its
        pitch is left out: the standing head's forward points 30 degrees down, which hid the
        far eye of a three-quarter view (azimuth 45) behind the head's side."""
        qw, _ = self.body.globals(self.output)
        f = np.array(qrot(qw[self.body.part_body["head"]], (1.0, 0.0, 0.0)))
        level = np.array([f[0], 0.0, f[2]])
        n = float(np.linalg.norm(level))
        f = level / n if n > 1e-6 else f
        cam = self.camera
        return float(f @ cam.right), float(f @ cam.up), float(-(f @ cam.eye))

    def frame(self, t: float) -> dict:
        """The output record of DESIGN.md's ``pose`` for the current output posture."""
        pts = self._points(self.output)
        parts = pts[self._np:]
        names = list(self.body.names) + list(PARTS)
        world = pts @ MODEL_TO_WORLD.T
        u = self.clock.u if self.mode == "action" and self.clock is not None else None
        return {"t": round(float(t), 6), "mode": self.mode,
                "action": self.clock.action.name if u is not None else None,
                "action_time": None if u is None else round(u * self.clock.action.duration, 5),
                "parts": dict(zip(PARTS, np.round(self._drawn(parts), 5).tolist())),
                "joints": dict(zip(names, np.round(world, 5).tolist())),
                "touches": {str(i): f.part for i, f in sorted(self.fingers.items())}}

    def _fingers(self, t: float, touches: Mapping[int, tuple[float, float]]) -> None:
        for i in [i for i in self.fingers if i not in touches]:
            del self.fingers[i]
        free_before = {i: f.table.copy() for i, f in self.fingers.items() if f.part is None}
        parts = self._drawn(self._points(self.output)[self._np:])
        taken = False
        for i, (x, y) in touches.items():
            xy = np.array([float(x), float(y)])
            f = self.fingers.get(i)
            if f is None:
                f = self.fingers[i] = Finger(self._part_at(parts, xy))
                taken = True
            f.table = xy
            f.add(t, self.camera.to_screen(xy))
            if f.times[0] < t - PATH_S and len(f.times) > 8:  # keep the recent drag only
                f.drop_first(int(np.argmax(f.times >= t - PATH_S)))
        free_now = {i: f.table for i, f in self.fingers.items() if f.part is None}
        both = [i for i in free_now if i in free_before]
        if len(free_now) >= 2 and len(both) >= 2 and not taken:
            move = common_motion(np.array([free_now[i] - free_before[i] for i in both]))
            if np.any(move != 0.0):
                self.turn(-move[0] * TURN_DEG_PER_M, -move[1] * TURN_DEG_PER_M)

    def _on_table(self, pose: Pose) -> Pose:
        """``pose`` moved sideways (along the screen's x, the horizontal ``camera.right``) just
        enough that every drawn point lies within the table's x extent (``TABLE_MARGIN`` inside
        it), if one is beyond it.
        Actions travel (a punch steps 1.9 m, character metres) from wherever the character
        stands: three punches in a row took the hand to x = 1.26 m on a 1.2 m table."""
        x = self.camera.table(self._points(pose))[:, 0]
        lo, hi, m = float(x.min()), float(x.max()), TABLE_MARGIN
        shift = m - lo if lo < m else (self.table[0] - m - hi if hi > self.table[0] - m else 0.0)
        if shift == 0.0 or hi - lo > self.table[0] - 2 * m:
            return pose
        return Pose(pose.root + self.camera.right * (shift / self.scale), pose.rots.copy())

    def _part_at(self, parts: np.ndarray, xy: np.ndarray) -> str | None:
        """The part a finger put down at ``xy`` (table metres) takes, of the projected ``parts``
        (6, 2): the nearest within ``reach``; of parts drawn about as near (within
        ``OVERLAP`` x reach more), the one in front, which the touch's half-line meets first.
        From the side the feet are drawn 0.015 m apart (0.3 m tall, view 90,15) and the nearer
        on the table was picked, the hidden foot as often as the seen one."""
        d = np.linalg.norm(parts - xy, axis=1)
        k = int(np.argmin(d))
        if d[k] > self.reach:
            return None
        near = np.flatnonzero((d <= d[k] + OVERLAP * self.reach) & (d <= self.reach))
        if len(near) > 1:
            depth = self._points(self.output)[self._np + near] @ self.camera.eye
            k = int(near[np.argmin(depth)])
        return PARTS[k]

    def _constraints(self) -> tuple[list[str], np.ndarray]:
        held = [(f.part, f.path[-1]) for f in self.fingers.values() if f.part is not None]
        return [p for p, _ in held], np.array([s for _, s in held]).reshape(-1, 2)

    def _points(self, pose: Pose) -> np.ndarray:
        """:meth:`Humanoid.points` of ``pose``, remembered for the last few pose objects (the
        target and output are each read several times a frame and never changed in place)."""
        hit = self._memo.get(id(pose))
        if hit is not None and hit[0] is pose:
            return hit[1]
        if len(self._memo) >= 4:
            self._memo.pop(next(iter(self._memo)))
        pts = self.body.points(pose)
        self._memo[id(pose)] = (pose, pts)
        return pts

    def _grounded(self, pose: Pose, parts: np.ndarray | None = None) -> set[str]:
        parts = self.body.parts(pose) if parts is None else parts
        return {p for p in ("left_foot", "right_foot") if parts[PARTS.index(p)][1] < GROUND}

    def _solve(self, pose: Pose, names: list[str], targets: np.ndarray, skip: str | None = None,
               keep_feet: bool = True, held: set[str] | frozenset = frozenset()) -> Pose:
        """CCD toward the touches (each limited to 0.2 m, ``ik.MAX_CORRECTION``), planted feet
        kept in place. The ``held`` parts' goals are not limited: a part held by a secondary
        finger stays under it (fixed, section 7) as far as its chain reaches while the action
        moves the body. Limited to 0.2 m it went with the travelling body: held part's median
        distance from its finger over the action (tests/touch_pose/test_held_during_action.py,
        table m at 0.3 m tall, view 90,15) walk 0.126 -> 0.018, punch 0.133 -> 0.051, kick
        0.095 -> 0.006; over the posing second after it (held through the action) 0.102 ->
        0.063 (walk), 0.099 -> 0.028 (punch), the head held through the walk 0.072 -> 0.000."""
        parts = self.body.parts(pose)
        goals: dict[str, np.ndarray] = {}
        for name, s in zip(names, targets):
            if name == skip:
                continue
            cur = parts[PARTS.index(name)]
            ray = self.camera.ray_point(s, cur)
            goals[name] = ray if name in held else limit_goal(cur, ray)
        if keep_feet:
            prev = self._points(self.target)[self._np:]
            for foot in self._grounded(self.target, prev):
                if foot not in goals:
                    goals[foot] = prev[PARTS.index(foot)]
        return self.ccd.solve(pose, goals, legs=keep_feet) if goals else pose

    def _posing(self, dt: float) -> None:
        names, targets = self._constraints()
        if not names:  # the posture stays (where the ended action left it, at the base)
            if self.handover is not None:
                self.target = self._handed_over(self.handover.at_base, dt)
            return
        view, offset = yaw_view(self.camera.matrix, self.base, self.yaw)
        idx = np.array([PARTS.index(n) for n in names])
        blend = self.m.posing.synthesize(idx, targets, view, offset)
        pose = place(blend.pose, self.base, self.yaw)
        self.target = self._handed_over(self._solve(pose, names, targets,
                                                    held=self._held_through_action()), dt)
        match = self._recognise(view) if self.recognising else None
        if match is not None:
            # the action's posture is taken over at once (tracking control smooths the switch,
            # section 5). Blended in from posing's target over 0.3 s (root lerped, joints
            # slerped), a spin kick recognised at generalised time 0.61 swayed less (parts'
            # largest move a frame 61.3 -> 53.3 mm, drawing x offset 0.072 -> 0.021 m) but the
            # primary part lagged its finger more (bench/touch_pose_rest.py follow_1x 0.108 ->
            # 0.110 m; blending every action 0.132 m); pulling that part to its finger by IK
            # while blending turned the target 165 degrees in a frame (70 at once); shifting
            # the root to bring it toward the clip's made up the lag only with a larger root
            # step a frame (spin kick 66-83 -> 86-112 mm at follow_1x 0.108).
            self.mode, self.handover = "action", None
            self.clock = ActionClock(match.action, match.start_u)
            self.action_blend = None
            self.action_base = (self.base.copy(), self.yaw)

    def close(self) -> None:
        if self.physics is not None:
            self.physics.close()
            self.physics = None


def _yaw_matrix(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
