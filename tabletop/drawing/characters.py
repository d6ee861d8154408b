"""Every character kind, drawn with presence: filled anti-aliased bodies on a soft glow, limbs
with thickness and joints, eyes that blink and look at what the character attends to.

A :class:`Pose` says where and how a character stands on screen this frame (pixels, screen
radians with y down, opacity, size factor, breathing, blink, squash and stretch, gaze); the
drawing functions are pure over (surface, state, pose).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import pygame

from tabletop.drawing import character_kernel as K
from tabletop.drawing import pose_kernel, raster
from tabletop.drawing import primitives as P
from tabletop.drawing.discs import discs
from tabletop.drawing.fit import rigid_onto
from tabletop.drawing import screens
from tabletop.drawing.palette import (EYE_WHITE, INK, TABLE, Color, fade, level, lighten,
                                      remember, shade)
from tabletop.drawing.reading import Reading
from tabletop.drawing.topology import face_loops, hybrid_parts, topology
from tabletop.frames import CharacterState
from tabletop.table_map import TableToScreen

# Reactor body outline in units of its length, nose along +x (an egg, fuller at the front).
_T = np.linspace(0.0, 2 * math.pi, 28, endpoint=False)
REACTOR_BODY = np.stack([0.5 * np.cos(_T), 0.34 * np.sin(_T) * (1 + 0.14 * np.cos(_T))], axis=1)
REACTOR_EYES = np.array([(0.24, 0.13), (0.24, -0.13)])


@dataclass
class Pose:
    """A character's on-screen placement for one frame.

    ``center`` (px), ``angle`` (screen radians of its heading, y down), ``ppm`` (pixels per
    metre there), ``alpha`` (0..1), ``scale`` (size factor), ``breath`` (size factor),
    ``stretch`` (length factor along ``motion`` screen radians), ``blink`` (eye opening 0..1),
    ``gaze`` (screen radians the eyes look along), ``color`` (body colour before fading),
    ``phase`` (radians of its stepping cycle), ``light`` (strength factor of its glow: 0 for a
    faint hint of a pose, which casts no light), ``ground`` (the colour its opacity fades it
    toward: the table's, or black for a figure drawn as light to add onto what is under it).
    """

    center: tuple[float, float]
    angle: float
    ppm: float
    alpha: float = 1.0
    scale: float = 1.0
    breath: float = 1.0
    stretch: float = 1.0
    motion: float = 0.0
    blink: float = 1.0
    gaze: float = 0.0
    color: Color = (240, 170, 60)
    phase: float = 0.0
    light: float = 1.0
    ground: Color = TABLE

    def body(self, k: float = 1.0) -> Color:
        return fade(shade(self.color, k), self.alpha, self.ground)


_inks: dict[tuple, tuple[int, ...]] = {}


def inks(color: Color, alpha: float, ground: Color = TABLE) -> tuple[int, ...]:
    """A character's colours at opacity ``alpha`` over ``ground`` (the table), packed 0xRRGGBB
    as the compiled drawing takes them (remembered: the same few recur frame after frame): its
    body shaded by 0.62, 0.68, 0.7 and 0.72 and whole, lightened by 0.18 and 0.35, eye white
    and ink. Over black (a pose drawn as light to add onto the view, :mod:`light`) the eyes
    are of the body's own light, its white the lightest and its pupils the body: an eye white
    faded toward black was light, but a pupil of ink was none, a dark hole in the faint figure.
    """
    # remembered by the opacity's 1/128 step, all they depend on (palette.fade): by the
    # opacity itself, a hinted pose's strength (smoothed toward its probability) or a fading
    # character missed every frame, ~0.1 ms each (bench/view.py's hinted scene, its first
    # pass: 6.4 misses a frame, 0.59 ms)
    a = level(alpha)
    key = (color, a, ground)
    try:
        return _inks[key]
    except KeyError:
        pass
    except TypeError:          # a colour given as a list
        key = (tuple(color), a, tuple(ground))
        if key in _inks:
            return _inks[key]
    g, w = key[2], a / 128.0
    g0, g1, g2 = g
    # each faded as palette.fade fades it (its mix's arithmetic, to the bit), not through its
    # three remembered layers: a miss 60 -> ~10 us
    out = tuple((int(round(g0 + (r - g0) * w)) << 16) | (int(round(g1 + (gr - g1) * w)) << 8)
                | int(round(g2 + (b - g2) * w)) for r, gr, b in _ink_bases(key[0], g))
    return remember(_inks, key, out, 4096)


_bases: dict[tuple, tuple[Color, ...]] = {}


def _ink_bases(c: Color, g: Color) -> tuple[Color, ...]:
    """:func:`inks`' nine colours of a character of colour ``c`` before they are faded over
    ``g`` (remembered)."""
    key = (c, g)
    out = _bases.get(key)
    if out is None:
        eyes = (lighten(c, 0.35), c) if g == (0, 0, 0) else (EYE_WHITE, INK)
        out = remember(_bases, key, tuple(shade(c, k) for k in (0.62, 0.68, 0.7, 0.72, 1.0))
                       + (lighten(c, 0.18), lighten(c, 0.35), *eyes), 1024)
    return out


def _squash(pose: Pose) -> tuple[float, float, float, float]:
    """The 2x2 map (row vectors, ``p @ S``, as four floats s00, s01, s10, s11) that stretches
    local points (x along the heading) by ``pose.stretch`` along the motion and squashes them
    across it."""
    k = pose.stretch
    if abs(k - 1.0) < 1e-3:
        return 1.0, 0.0, 0.0, 1.0
    d = pose.motion - pose.angle
    c, s = math.cos(d), math.sin(d)
    cs = c * s * (k - 1.0 / k)
    return k * c * c + s * s / k, cs, cs, k * s * s + c * c / k


# Characters are drawn afresh every frame rather than blitted from cached renders keyed on their
# drawing inputs: in bench/view.py's busy scene no figure's points repeat from one frame to the
# next, and even rounded to whole pixels a pose recurs in only 15-50 % of frames, while a hit
# still blits the figure's whole rectangle with per-pixel alpha (a 221 px square costs ~0.1 ms
# with a cold cache here) and a miss draws the figure twice (on black and on white, for its
# coverage) and extracts it: more lost on misses than won on hits. Each character's shapes are
# rasterised by one compiled call (tabletop.drawing.character_kernel) instead.
_BODY_UV = np.ascontiguousarray(REACTOR_BODY, dtype=np.float64)
_EYES_UV = np.ascontiguousarray(REACTOR_EYES, dtype=np.float64)


def bodies(chars: Sequence[CharacterState], table: TableToScreen) -> list[pygame.Rect]:
    """Where each character's body lies on the window (pixels; the studio's marks and broken
    states left out): a figure's, face's or hybrid's points' bounds with its limbs' reach
    (0.08 of its size), another's 0.55 of its size about its centre."""
    out = []
    for c in chars:
        if c.kind == "studio" or not (math.isfinite(c.x) and math.isfinite(c.y)
                                      and 0.0 < c.size < 100.0):
            continue
        figure = c.points is not None and len(c.points) > 0
        reach = (0.08 if figure else 0.55) * c.size
        xy = c.points if figure else ((c.x, c.y),)
        px = table.points(np.asarray(xy, dtype=np.float64).reshape(-1, 2))
        px = px[np.isfinite(px).all(axis=1)]
        if len(px):
            pad = reach * table.scale_at(c.x, c.y) + 2
            (x0, y0), (x1, y1) = px.min(axis=0) - pad, px.max(axis=0) + pad
            out.append(pygame.Rect(int(x0), int(y0), int(x1 - x0) + 1, int(y1 - y0) + 1))
    return out


GLOWS = {"reactor": (0.8, 0.0), "figure": (0.42, 6.0), "face": (0.62, 6.0)}   # (of size, + px)


def glow_radius(part: str, size: float, ppm: float) -> float:
    """The radius (px) of the glow under a ``part`` ("reactor", "figure" or "face") of ``size``
    metres drawn at ``ppm`` pixels per metre."""
    k, px = GLOWS[part]
    return k * size * ppm + px


def prepare_glows(parts: Sequence[tuple[str, float]], ppm: float) -> None:
    """Make the glows of ``parts`` ((part, size m) pairs) at ``ppm`` pixels per metre before
    they are drawn: each new glow size made in a frame cost that frame 1-9 ms (examples/mop.yaml,
    its 3rd and 4th frames, 12 ms in all)."""
    for part, size in parts:
        P.prepare_glow(glow_radius(part, size, ppm))


def configured_parts(engines: Sequence[dict]) -> list[tuple[str, float]]:
    """The glowing parts ((part, size m)) of the characters a configuration's ``engines`` name:
    Puppet Master's reactors, MOP's characters (a hybrid's body a figure; its face's size is
    its points', known only when drawn)."""
    out = []
    for e in engines:
        if e.get("kind") == "puppet_master" and isinstance(e.get("size"), (int, float)):
            out.append(("reactor", float(e["size"])))
        elif e.get("kind") == "mop":
            out += [("face" if ch.get("kind") == "face" else "figure", float(ch["size"]))
                    for ch in e.get("characters", ()) if isinstance(ch.get("size"), (int, float))]
    return out


def draw_reactor(surf: pygame.Surface, c: CharacterState, pose: Pose) -> pygame.Rect | None:
    """The default character: an egg-shaped creature, nose along its heading, on a soft glow,
    with a lighter belly and two eyes. Returns the rectangle it touched."""
    L = c.size * pose.ppm * pose.scale
    if L < 2:
        return None
    # One 2x2 map (local units -> pixels: squash, size, heading); the body breathes in it.
    ca, sa = math.cos(pose.angle), math.sin(pose.angle)
    s00, s01, s10, s11 = _squash(pose)
    M = np.array(((s00 * ca - s01 * sa) * L, (s00 * sa + s01 * ca) * L,
                  (s10 * ca - s11 * sa) * L, (s10 * sa + s11 * ca) * L))
    cx, cy = pose.center
    # The glow keeps the grown-up size while the body grows in (its strength fades in): one
    # cached light per character instead of a new one every few frames of a fade.
    touched = P.glow(surf, pose.center, glow_radius("reactor", c.size, pose.ppm), pose.color,
                     0.36 * pose.alpha * pose.light)
    # Little feet peeking out at the sides, stepping while it moves.
    step = 0.1 * min(1.0, (pose.stretch - 1.0) / 0.1) * math.sin(pose.phase)
    # (every scalar a float: a kernel given an int where it was compiled for a float compiles
    # again, seconds, in the middle of a frame)
    foot, _, _, dark, body, _, belly, white, ink = inks(pose.color, pose.alpha, pose.ground)
    raster.draw(surf, K.reactor, _BODY_UV, _EYES_UV, M, float(pose.breath), float(cx),
                float(cy), float(L), ca, sa, float(step), foot, dark, body, belly,
                float(pose.blink), float(pose.gaze), float(pose.angle), white, ink)
    # (everything of it lies within 0.9 L of its centre, its feet and stretch included)
    return P.union([touched, P.disc_rect(int(cx), int(cy), int(0.9 * L * pose.stretch) + 3)])


_KINDS = {"skeleton": K.SKELETON, "creature": K.CREATURE, "sprite": K.SPRITE}
_WIDTHS = {"skeleton": 0.03, "sprite": 0.075}      # a limb's half-width, of the figure's size


def _posed(c: CharacterState, pose: Pose, xy: np.ndarray, H: np.ndarray) -> tuple | None:
    """A figure's points (table metres ``xy``, mapped to pixels by ``H``) scaled about the
    pose's centre by its growth and breath, in one compiled call: (points px, their bounds
    (x0, y0, x1, y1) px, the figure's size px); None when there is nothing finite to draw."""
    pts, x0, y0, x1, y1 = pose_kernel.posed(H, xy, float(pose.center[0]), float(pose.center[1]),
                                            float(pose.scale * pose.breath))
    if len(pts) == 0:                                          # NaN or inf anywhere
        return None
    return pts, (x0, y0, x1, y1), c.size * pose.ppm * pose.scale


def draw_figure(surf: pygame.Surface, c: CharacterState, pose: Pose, xy: np.ndarray,
                H: np.ndarray, head: bool = True,
                spans: np.ndarray | None = None) -> pygame.Rect | None:
    """An articulated figure (skeleton, creature, sprite sheet) of points ``xy`` (N x 2 table
    metres, mapped to pixels by ``H``): limbs with thickness and joints, the spine (from the
    first bone, first children on) thickest, a head with eyes at the spine's end (unless
    ``head`` is False). ``spans``: each row's pixels drawn marked in it (a hinted pose's,
    :class:`tabletop.drawing.light.AddedLight`; it casts no glow). Returns the rectangle it
    touched."""
    posed = _posed(c, pose, xy, H)
    if posed is None:
        return None
    pts, box, fig = posed
    # The glow's size follows the figure's grown-up size, not its pose or its growing in (its
    # strength fades in): one cached light per figure. It lies about the figure's points, as a
    # face's about its head's: about their bounding box, an arm stretched out (a touch-posed
    # hand dragged away) pulled it over the empty table beside the body.
    strength = 0.26 * pose.alpha * pose.light
    touched = None
    if strength > P.GLOW_SHOWN:       # (a hinted pose casts none: its points' mean not taken)
        mx, my = (np.add.reduce(pts, axis=0) / len(pts)).tolist()   # (= mean, faster)
        touched = P.glow(surf, (mx, my), glow_radius("figure", c.size, pose.ppm), pose.color,
                         strength)
    topo = topology(len(pts), c.bones)
    w0 = max(1.5, _WIDTHS.get(c.kind, 0.045) * fig)
    _, dark, _, _, body, light, _, white, ink = inks(pose.color, pose.alpha, pose.ground)
    if topo is None:
        r = max(2.0, 0.03 * fig)
        raster.draw(surf, discs, pts, float(r + 0.5), body, spans)
        return P.union([touched, P.box(box, r + 2)])
    rel, _, tp = topo
    wspine = w0 * (1.25 if c.kind == "skeleton" else 1.0)
    raster.draw(surf, K.figure, pts, rel, tp, _KINDS.get(c.kind, K.OTHER), float(w0),
                float(wspine), float(fig), bool(head), dark, body, light, float(pose.angle),
                float(pose.gaze), float(pose.blink), white, ink,
                *pose_kernel.facing_px(H, c.x, c.y, c.facing), spans)
    return P.union([touched, P.box(box, wspine + 0.08 * fig + 2)])


def draw_face(surf: pygame.Surface, c: CharacterState, pose: Pose, xy: np.ndarray,
              H: np.ndarray, hint: tuple[Pose, np.ndarray] | None = None,
              spans: np.ndarray | None = None) -> pygame.Rect | None:
    """A face of points ``xy`` (N x 2 table metres, mapped to pixels by ``H``): its first closed
    loop is the head (filled, on a glow), smaller closed loops are eyes (white with pupils
    looking along the gaze, blinking) or the mouth (dark), open strokes are brows and nose
    drawn thick. ``hint``: a suspected expression (its faint pose, its points) whose features
    show faintly on the head under the face's own (MOP early feedback: drawn on its own, a
    faint face lay wholly under the opaque face and was never seen). ``spans``: as
    :func:`draw_figure`'s. Returns the rectangle it touched."""
    posed = _posed(c, pose, xy, H)
    if posed is None:
        return None
    pts, box, fig = posed
    loops = face_loops(len(pts), tuple(c.bones))
    if loops is None:
        return None
    lp, head = loops
    glow = None
    if len(head):
        mx, my = (np.add.reduce(pts[head], axis=0) / len(head)).tolist()   # (= mean, faster)
        glow = P.glow(surf, (mx, my), glow_radius("face", c.size, pose.ppm), pose.color,
                      0.32 * pose.alpha * pose.light)
    _, _, shadow, _, body, _, _, white, ink = inks(pose.color, pose.alpha, pose.ground)
    stroke = float(max(1.5, 0.022 * fig))
    look = (float(pose.blink), float(pose.gaze), float(pose.angle))
    ghost = _posed(c, hint[0], hint[1], H) if hint is not None else None
    if ghost is None:
        raster.draw(surf, K.face, pts, lp, stroke, shadow, body, white, ink, *look,
                    K.HEAD + K.FEATURES, spans)
        return P.union([P.box(box, 0.06 * fig + 2), glow])
    raster.draw(surf, K.face, pts, lp, stroke, shadow, body, white, ink, *look, K.HEAD, spans)
    # the suspected features at the hint's opacity over the face's own skin
    gwhite, gink = inks(pose.color, hint[0].alpha, pose.body())[7:]
    raster.draw(surf, K.face, ghost[0], lp, stroke, shadow, body, gwhite, gink, *look,
                K.FEATURES, spans)
    raster.draw(surf, K.face, pts, lp, stroke, shadow, body, white, ink, *look, K.FEATURES,
                spans)
    return P.union([P.box(box, 0.06 * fig + 2), P.box(ghost[1], 0.06 * fig + 2), glow])


def draw_hybrid(surf: pygame.Surface, c: CharacterState, pose: Pose, xy: np.ndarray,
                H: np.ndarray, hint: tuple[Pose, np.ndarray] | None = None,
                spans: np.ndarray | None = None) -> pygame.Rect | None:
    """A hybrid character: its body drawn as a creature's (no head of its own) and its face
    drawn as a face where the head would be. ``xy``: every point (table metres, mapped to
    pixels by ``H``); ``hint``: a suspected pose, its face's features shown faintly on the
    face (:func:`draw_face`); ``spans``: as :func:`draw_figure`'s. Returns the rectangle it
    touched."""
    parts = hybrid_parts(len(xy), tuple(c.bones))
    if parts is None or c.points is None:
        return draw_figure(surf, c, pose, xy, H, spans=spans)
    k, body_bones, face_bones = parts
    face_m = np.asarray(c.points)[k:]
    if not np.all(np.isfinite(face_m)):
        return None
    # the parts as the drawing reads them (kind, size, bones; made directly: a
    # dataclasses.replace of every field cost twice as much, ~40 us a part)
    body = CharacterState(c.name, c.x, c.y, c.heading, "creature", c.size, c.color, None,
                          body_bones)
    face = CharacterState(c.name, c.x, c.y, c.heading, "face",
                          float(np.ptp(face_m, axis=0).max()), c.color, None, face_bones)
    face_hint = None
    if hint is not None and len(hint[1]) == len(xy):
        # the suspected face carried onto the live one (its head's outline laid on this one's):
        # where the suspected body stands (the mime's jump lifts its head 2 cm, 17 px at
        # 1280x720) its features were drawn on this face 185 px off its own, a second face
        loops = face_loops(len(xy) - k, face_bones)
        ref = loops[1] if loops is not None else np.zeros(0, dtype=np.int64)
        face_hint = (hint[0], rigid_onto(np.asarray(hint[1], dtype=np.float64)[k:],
                                         np.asarray(xy[k:], dtype=np.float64), ref))
    return P.union([draw_figure(surf, body, pose, xy[:k], H, False, spans),
                    draw_face(surf, face, pose, xy[k:], H, face_hint, spans)])


# A played-back main take (the studio's sequential training) is the main's puck's ghost: a
# neutral ring (GHOST_RGB at GHOST_ALPHA) with a notch along its heading, "main" beside it: a
# faint copy of the character would put two of the reactor on the table, and the designer,
# playing the reactor against it, would read it as a second reactor.
GHOST_ALPHA, GHOST_RGB = 0.6, (220, 220, 220)


def draw_playback(target: pygame.Surface, pose: Pose, puck_radius: float,
                  reading: Reading) -> pygame.Rect:
    """The main's puck's ghost (:data:`GHOST_RGB`): a ring of radius 1.5 puck radii
    (``puck_radius``, metres), a notch along its heading and "main" under it, upright on the
    table for its reader (``reading``). Returns the rectangle drawn (pixels)."""
    k = GHOST_ALPHA * pose.alpha
    ink = tuple(int(v * k) for v in GHOST_RGB)
    cx, cy = pose.center
    r = max(6, round(1.5 * puck_radius * pose.ppm))
    ring = pygame.draw.circle(target, ink, (cx, cy), r, width=3)
    a = pose.angle
    pygame.draw.line(target, ink, (cx + 0.6 * r * math.cos(a), cy + 0.6 * r * math.sin(a)),
                     (cx + 1.3 * r * math.cos(a), cy + 1.3 * r * math.sin(a)), 3)
    img = reading.turn(screens.font(max(14, r)).render("main", True, ink))
    word = target.blit(img, reading.at(img.get_size(), reading.offset((cx, cy), up=-1.4 * r),
                                       (0.5, 0.0)))
    return ring.inflate(r, r).union(word)
