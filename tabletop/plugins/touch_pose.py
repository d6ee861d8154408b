"""Engine ``touch_pose``: drag a projected humanoid's body parts to pose it and make it act.

Config::

    - kind: touch_pose
      name: poser
      at: [0.6, 0.4]        # table metres where the character stands (default: the centre)
      height: 0.3           # metres tall as drawn on the table
      view: [90, 15]        # camera azimuth (0 front, 90 its right side) and elevation, degrees
      reach: 0.04           # metres: a touch farther than this from every part picks nothing
      physics: true         # physics-based secondary motion (pybullet)
      mouse: true           # also take fingers made with the mouse in the view
      color: [120, 220, 255]
      library: pose_actions # actions designed at the table (the studio), loaded at start

Touches come from every source on the bus (TUIO cursors, the scripted source, recordings) plus,
with ``mouse``, the view's pointer (:mod:`tabletop.pointer`). Two fingers dragged on empty table
turn the camera; so do the arrow keys (``camera.left/right/up/down``, 15 degrees a press).
Actions designed at the table (:mod:`behaviors.touch_pose.designed`, recorded through the studio)
are kept in ``library`` and known from the start; a bad one is logged, skipped and listed in a
kiosk's status (``behavior_errors``) until it is fixed.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

from tabletop.frames import CharacterState, Frame
from tabletop.registry import BuildContext
from tabletop.schema import Bool, Context, FilePath, ListOf, Number, Optional_, Record

log = logging.getLogger("tabletop")

KEY_TURN_DEG = 15.0
TURNS = {"camera.left": (-KEY_TURN_DEG, 0.0), "camera.right": (KEY_TURN_DEG, 0.0),
         "camera.up": (0.0, KEY_TURN_DEG), "camera.down": (0.0, -KEY_TURN_DEG)}



def _check_view(options: dict, path: str, ctx: Context) -> None:
    """The view's elevation within the bounds ``tabletop pose --view`` takes (``view: [90,
    1000]`` was accepted and turned the character upside down)."""
    from behaviors.touch_pose.humanoid import VIEW_ELEVATION_DEG
    lo, hi = VIEW_ELEVATION_DEG
    el = options["view"][1]
    if not lo <= el <= hi:
        raise ctx.error(f"{path}.view[1]", f"elevation {el:g} degrees is out of range; expected "
                                           f"{lo:g} to {hi:g} (90 looks straight down)")


SCHEMA = Record({
    "at": Optional_(ListOf(Number(), min_len=2, max_len=2), doc="[x, y] metres; default centre"),
    "height": Number(0.3, unit="metres", lo=0.05, hi=3.0, doc="metres tall on the table"),
    "view": ListOf(Number(), default=[0.0, 15.0], min_len=2, max_len=2,
                   doc="[azimuth, elevation] degrees"),
    "reach": Number(0.04, unit="metres",
                    lo=0.005, hi=0.5, doc="metres from a part within which a touch picks it"),
    "physics": Bool(True, doc="physics-based secondary motion"),
    "mouse": Bool(True, doc="take the view's mouse fingers too"),
    "color": ListOf(Number(integer=True, lo=0, hi=255), default=[120, 220, 255], min_len=3,
                    max_len=3),
    "library": FilePath("pose_actions", must_exist=False, kind="dir", embed=True,
                        doc="folder of the actions designed at the table"),
}, check=_check_view)


class TouchPoseEngine:
    """The bus side of :class:`behaviors.touch_pose.engine.TouchPose`."""

    def __init__(self, name: str, options: dict[str, Any], table: tuple[float, float]) -> None:
        from behaviors.touch_pose.engine import TouchPose
        self.name = name
        view = options["view"]
        self.core = TouchPose(table, options["height"], view[0], view[1], options["reach"],
                              physics=options["physics"],
                              at=tuple(options["at"]) if options["at"] else None)
        self.mouse = bool(options["mouse"])
        self.color = tuple(int(c) for c in options["color"])
        self.library = Path(options["library"])
        from behaviors.touch_pose.designed import load_library
        from tabletop.kiosk.watch import tree_signature
        self.library_read = tree_signature(self.library)   # the studio poller's first baseline
        actions, self.problems = load_library(self.library, self.core.body)
        for a in actions:
            self.core.add_action(a)
        self.designed = [a.name for a in actions]
        for p in self.problems:
            log.error("touch-pose action skipped: %s", p)
        self.problem = "; ".join(self.problems)   # (a recording's started_without)

    @property
    def start_problems(self) -> list[str]:
        """The library's files the character goes without (the status's behavior_errors),
        as its studio target last read the folder."""
        return self.problems

    def step(self, frame: Frame) -> tuple[CharacterState, ...]:
        for c in frame.commands:
            if c in TURNS:
                self.core.turn(*TURNS[c])
        touches = {t.id: (t.x, t.y) for t in frame.touches}   # the mouse's too (pointer.py)
        core = self.core
        core.step(frame.t, touches, record=False)
        pts = core.table_points()
        pelvis = pts[0]
        acting = core.mode == "action" and core.clock is not None
        action = core.clock.action.name if acting else None
        cam = core.camera
        held = sum(f.part is not None for f in core.fingers.values())
        label = (f"{core.mode} {action + ' ' if action else ''}view {cam.azimuth:.0f},"
                 f"{cam.elevation:.0f} touches {held}")
        return (CharacterState(self.name, float(pelvis[0]), float(pelvis[1]), 0.0, kind="humanoid",
                               size=core.scale * core.stand_height, color=self.color,
                               points=pts, bones=core.body.bones,
                               progress=core.clock.u if acting else None, action=action,
                               label=label, facing=core.head_facing()),)

    def close(self) -> None:
        self.core.close()


def build(options: dict, ctx: BuildContext) -> TouchPoseEngine:
    return TouchPoseEngine(options.get("name") or "touch_pose", options, ctx.table)
