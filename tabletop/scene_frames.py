"""A busy table for the view's tests and benchmarks: eight characters of every kind (three
Puppet Master reactors, two MOP humanoids, a creature, a face, a sprite-sheet bird), all moving,
and sixteen pucks wandering (some coasting), as Frames at 60 Hz; :func:`hinted_frames`: three
of them suspecting an action (MOP early feedback)."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from behaviors.mop.creatures import FaceModel, creature_clips, creature_skeleton, face_clips
from behaviors.mop.puppetry import FaceRig, HumanoidRig, PlanarRig
from behaviors.mop.sprites import sprite_sheet_from_mapping
from behaviors.motion.deepmimic import ROOT_SCALE, humanoid_urdf, load_motion
from behaviors.motion.skeleton import ProjectedFigure, Projection, load_urdf, place
from tabletop.frames import CharacterState, Frame, Puck

ROOT = Path(__file__).resolve().parents[1]
TABLE = (1.2, 0.8)


def busy_frames(n: int, rate_hz: float = 60.0, pucks: int = 16) -> list[Frame]:
    """``n`` consecutive frames of the busy table."""
    human = HumanoidRig(ProjectedFigure(load_urdf(humanoid_urdf()),
                                        Projection(view_yaw=0.5, elevation=0.25), ROOT_SCALE))
    walk, kick = load_motion("walk"), load_motion("kick")
    creature = PlanarRig(creature_skeleton())
    c_walk = creature_clips()["walk"]
    face = FaceRig(FaceModel())
    talk = face_clips()["talk"]
    bird = sprite_sheet_from_mapping(json.loads((ROOT / "examples/mop/bird.json").read_text()),
                                     "bird.json")
    flap = bird.cycle()
    colors = [(240, 110, 150), (240, 170, 60), (120, 190, 255), (240, 170, 60), (255, 200, 120),
              (90, 220, 120), (120, 180, 255), (250, 250, 200)]
    frames = []
    for k in range(n):
        t = k / rate_hz
        chars = []
        for i, name in enumerate(("lover", "bully", "afraid")):
            a = 0.4 * t * (1 + 0.3 * i) + 2.1 * i
            x, y = 0.6 + 0.35 * math.cos(a), 0.4 + 0.22 * math.sin(1.3 * a)
            h = math.atan2(0.22 * 1.3 * math.cos(1.3 * a), -0.35 * math.sin(a))
            chars.append(CharacterState(name, x, y, h, size=0.08, color=colors[i],
                                        valid=i != 2))
        for i, (clip, x) in enumerate(((walk, 0.25), (kick, 0.95))):
            p = human.pose(clip, (t / clip.duration) % 1.0)
            chars.append(CharacterState(f"dancer{i}", x, 0.2, math.pi / 2, kind="skeleton",
                                        size=0.3, color=colors[3 + i],
                                        points=place(p, x, 0.2, math.pi / 2, 0.3),
                                        bones=human.bones))
        specs = ((creature, c_walk, "salamander", 0.75, 0.62, 0.0, 0.3, "creature"),
                 (face, talk, "face", 0.45, 0.6, math.pi / 2, 0.2, "face"),
                 (bird, flap, "bird", 0.2, 0.62, 0.3 * math.sin(t), 0.15, "sprite"))
        for j, (rig, clip, name, x, y, h, size, kind) in enumerate(specs):
            p = rig.pose(clip, (t / max(clip.duration, 1e-6)) % 1.0)
            chars.append(CharacterState(name, x, y, h, kind=kind, size=size, color=colors[5 + j],
                                        points=place(p, x, y, h, size), bones=rig.bones))
        pk = []
        for i in range(pucks):
            a = 0.5 * t + 2 * math.pi * i / pucks
            x = 0.6 + (0.25 + 0.02 * (i % 5)) * math.cos(a + 0.3 * math.sin(0.7 * t + i))
            y = 0.4 + (0.17 + 0.01 * (i % 3)) * math.sin(1.5 * a)
            pk.append(Puck(i, x, y, a * 2, vx=-0.12 * math.sin(a), vy=0.1 * math.cos(a),
                           state="coasting" if i % 5 == 0 else "seen"))
        frames.append(Frame(seq=k, t=t, pucks=tuple(pk), characters=tuple(chars)))
    return frames


HINTED = ("dancer0", "salamander", "bird")   # three MOP characters of three kinds


def hinted_frames(frames: list[Frame], names: tuple[str, ...] = HINTED,
                  shift_m: float = 0.12) -> list[Frame]:
    """``frames`` with the characters ``names`` suspecting an action (MOP early feedback: not
    yet acting, a hinted pose at 0.8): their own pose ``shift_m`` metres towards the table's
    middle (across its length), drawn as an outline and named."""
    out = []
    for f in frames:
        chars = []
        for c in f.characters:
            if c.name in names and c.points is not None:
                dy = shift_m if c.y < TABLE[1] / 2 else -shift_m
                c = dataclasses.replace(c, valid=False, hints=(("circle", 0.8, 0.5),),
                                        hint_points=np.asarray(c.points) + (0.0, dy))
            chars.append(c)
        out.append(dataclasses.replace(f, characters=tuple(chars)))
    return out
