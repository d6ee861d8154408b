"""Action control of a touch-posed character (paper 003, section 5): an action recognised
from a drag runs on its clock toward the synthesised time; secondary touches by unlimited IK;
at its end the character goes back to posing where the action left it (within ``ROAM``),
posing's target faded in from the action's (``HANDOVER_S``, seconds). The engine is
:class:`behaviors.touch_pose.engine.TouchPose`."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from behaviors.motion.clips import quat_slerp
from behaviors.touch_pose.action import ActionClock, ActionModel, Match, recognise
from behaviors.touch_pose.fingers import Finger
from behaviors.touch_pose.humanoid import PARTS, Camera, Pose, yaw_of
from behaviors.touch_pose.latent import Blend, yaw_view
from behaviors.touch_pose.models import Models
from behaviors.touch_pose.samples import place


#: Seconds over which posing's target is faded in from the action's last target (root lerped,
#: joints slerped), also the time an action that ended beyond ``ROAM`` takes to come back to
#: the base: parts, the held one above all, move on from where the action left them. Taken over
#: at once, the held part jumped with the body brought back to the base, then moved back
#: the next frame (posing's first frame kept the action's planted feet). Its largest target step
#: over the action's last 10 frames and 8 frames after (table m, 0.3 m tall, view 90,15, physics
#: off): walk 0.047 -> 0.007, punch 0.132 -> 0.008, kick 0.033 -> 0.004 (over the action alone
#: 0.007, 0.008, 0.003); fading over 0.2 / 0.3 / 0.6 s: punch 0.016 / 0.011 / 0.008.
HANDOVER_S = 0.4
#: A finger whose points over the last ``REST_WINDOW`` s span at most ``REST_SPAN`` (table
#: metres, on either axis) rests (touches jittering by up to 2 mm each way span 4 mm): only then
#: may the action clock hold its time (``action.REST_BAND``), and while it holds, the posture
#: output when the hold took over is kept. Measured (bench/touch_pose_rest.py; the target's
#: most-moving part's back-and-forth while a finger with 1 mm of jitter rests, table m, median /
#: largest over views and seeds): the synthesised posture output at the held time, punch
#: 0.0068/0.145, wave 0.0060/0.070, bow 0.034/0.101; the sample motions' posture at the held
#: time 0.0001/0.001, 0/0.016, 0/0 but it leaves a finger resting after a drag back off its part
#: (bow back to 0.3: 0.0084 -> 0.035 m, wave 0.024 -> 0.054); the posture low-passed like the
#: time 0.0002/0.003 with the back drags at 0.022 (bow) and the kick's output swaying 0.02 m;
#: the posture kept, 0/0, 0.0001/0.009, 0/0, back drags as before. The span over 0.2 s
#: (``FINGER_WINDOW``) held a bow dragged back 5 times slower than its stroke (gap 0.0061 ->
#: 0.024 m); over 0.3 / 0.4 / 0.5 s it is 0.0072 / 0.0064 / 0.0062 (the wave 5x slower 0.0182
#: / 0.0181 / 0.0181, rest figures alike), and the time holds only where the posture does.
REST_SPAN = 0.005
REST_WINDOW = 0.5
#: Farthest the posing base may roam from where the character started (character metres).
ROAM = 1.0


class Handover(NamedTuple):
    """Posing's target fading in after an action (``HANDOVER_S``)."""
    from_pose: Pose   # the action's last target
    at_base: Pose     # the posture held while no finger poses (brought back within ``ROAM``)
    weight: float     # of posing's target, 0 -> 1



class ActionControl:
    """The action half of :class:`~behaviors.touch_pose.engine.TouchPose` (mode ``"action"``),
    and the fade back into posing after it."""

    m: Models
    camera: Camera
    scale: float
    fingers: dict[int, Finger]
    mode: str
    base: np.ndarray
    yaw: float
    target: Pose
    clock: ActionClock | None
    action_blend: tuple[ActionModel, Blend] | None
    rest_pose: Pose | None        # the last relative posture output (kept while a finger rests)
    action_base: tuple[np.ndarray, float]
    handover: Handover | None

    def excluded(self) -> set[str]:
        raise NotImplementedError

    def _constraints(self) -> tuple[list[str], np.ndarray]:
        raise NotImplementedError

    def _solve(self, pose: Pose, names: list[str], targets: np.ndarray, skip: str | None = None,
               keep_feet: bool = True, held: set[str] | frozenset = frozenset()) -> Pose:
        raise NotImplementedError


    def _handed_over(self, pose: Pose, dt: float) -> Pose:
        """``pose`` faded in from the action's last target over ``HANDOVER_S`` seconds."""
        if self.handover is None:
            return pose
        last = self.handover.from_pose
        w = min(self.handover.weight + dt / HANDOVER_S, 1.0)
        self.handover = None if w >= 1.0 else self.handover._replace(weight=w)
        return Pose(last.root + (pose.root - last.root) * w, quat_slerp(last.rots, pose.rots, w))

    def _held_through_action(self) -> set[str]:
        """Parts whose finger held them while an action ran (their IK stays unlimited)."""
        return {f.part for f in self.fingers.values() if f.held_through_action}

    def _finger_rests(self, part: str) -> bool:
        """Whether the finger on ``part`` has stayed within ``REST_SPAN`` over ``REST_WINDOW``."""
        for f in self.fingers.values():
            if f.part == part and len(f.times):
                if f.times[-1] - f.times[0] < REST_WINDOW:   # (a path just begun or restarted)
                    return False
                recent = f.path[int(np.searchsorted(f.times, f.times[-1] - REST_WINDOW)):]
                return float(np.ptp(recent, axis=0).max()) * self.scale <= REST_SPAN
        return False

    def _recognise(self, view: np.ndarray) -> Match | None:
        excluded = self.excluded()
        primary = {a.spec.part for a in self.m.actions if a.name not in excluded}
        for f in self.fingers.values():
            if f.part not in primary or len(f.times) < 3:
                continue  # no action this part could start from this view
            match = recognise(self.m.actions, f.part, f.path, f.times,
                              view, excluded)
            if match is not None:
                return match
        return None

    def _action(self, dt: float) -> None:
        clock = self.clock
        a = clock.action
        names, targets = self._constraints()
        base, yaw = self.action_base
        touching = a.spec.part in names
        synth = None
        if touching:
            view, offset = yaw_view(self.camera.matrix, base, yaw)
            idx = np.array([PARTS.index(n) for n in names])
            self.action_blend = (a, a.model.synthesize(idx, targets, view, offset))
            synth = self.action_blend[1].time
        u = clock.step(dt, synth, touching, touching and self._finger_rests(a.spec.part))
        # the sample motions' weights of this action's last synthesis are kept (equal before)
        last = self.action_blend[1] if self.action_blend and self.action_blend[0] is a else None
        # a resting finger's hold (REST_SPAN): the posture output when it took over is kept
        if not (synth is not None and clock.held and self.rest_pose is not None):
            if synth is not None and abs(u - synth) <= dt / a.duration:
                # close to the synthesised time (one frame's interval): the synthesised posture
                # is output (section 5). Measured over the six actions dragged at 1 and 1.5
                # times their pace from three views, the primary part's distance from the
                # finger while it drags fell from 0.034 to 0.030 m mean (kicks: medians
                # 0.06-0.09 -> 0.01-0.06 m); the largest joint turn per output frame stayed
                # 16.9 degrees. Landing exactly on it (a tolerance of 1e-9) used it too seldom
                # to matter (0.034 -> 0.033 m).
                blend: Blend = last
            else:
                blend = a.model.at_time(last, u)
            self.rest_pose = blend.pose
        pose = place(self.rest_pose, base, yaw)
        for f in self.fingers.values():
            f.held_through_action = f.held_through_action or f.part not in (None, a.spec.part)
        self.target = self._solve(pose, names, targets, skip=a.spec.part, keep_feet=False,
                                  held=set(names))
        if clock.done:
            self.mode, at_base = "posing", self.target
            if u >= 1.0:
                root = self.target.root
                d = np.array([root[0], root[2]])
                n = float(np.linalg.norm(d))
                self.base = d if n <= ROAM else d * (ROAM / n)
                self.yaw = yaw_of(self.target.rots[0])
                # an action that ended beyond ROAM (a punch steps 1.9 m) is brought back to
                # the base over HANDOVER_S (left where the action put it, it slid back only under
                # the next finger, 0.13 m on the table at 0.3 m tall, away from the touched part)
                shift = self.base - d
                at_base = Pose(root + np.array([shift[0], 0.0, shift[1]]), self.target.rots.copy())
            self.handover = Handover(self.target, at_base, 0.0)
            for f in self.fingers.values():
                f.restart()
