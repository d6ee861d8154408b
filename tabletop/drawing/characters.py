"""Every character kind, drawn with presence: filled anti-aliased bodies on a soft glow, limbs
with thickness and joints, eyes that blink and look at what the character attends to.

A :class:`Pose` says where and how a character stands on screen this frame (pixels, screen
radians with y down, opacity, size factor, breathing, blink, squash and stretch, gaze); the
drawing functions are pure over (surface, state, pose).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np
import pygame

from tabletop.drawing import primitives as P
from tabletop.drawing.palette import EYE_WHITE, INK, Color, fade, lighten, shade
from tabletop.frames import CharacterState

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
    faint hint of a pose, which casts no light).
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

    def body(self, k: float = 1.0) -> Color:
        return fade(shade(self.color, k), self.alpha)


def eyes(surf: pygame.Surface, pose: Pose, centers: Sequence[Sequence[float]],
         r: float) -> None:
    """Eyes of radius ``r`` px at screen ``centers`` ((x, y) pairs): white, a dark pupil turned
    along ``pose.gaze``, lids closing with ``pose.blink``."""
    if r < 1.5:
        return
    white, ink = fade(EYE_WHITE, pose.alpha), fade(INK, pose.alpha)
    gx, gy = math.cos(pose.gaze), math.sin(pose.gaze)
    for cx, cy in centers:
        if pose.blink > 0.97:
            P.disc(surf, white, (cx, cy), r)
        else:
            P.ellipse(surf, white, (cx, cy), r, max(0.6, r * pose.blink),
                      pose.angle + math.pi / 2, 14)
        if pose.blink > 0.45:
            px, py = cx + gx * r * 0.42, cy + gy * r * 0.42
            P.disc(surf, ink, (px, py), r * 0.52)
            P.disc(surf, white, (px - 0.25 * r * 0.5, py - 0.35 * r * 0.5), max(1.0, r * 0.16))


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


# The reactor's outline and eyes as plain floats: a few dozen points cost less as Python
# arithmetic than as tiny numpy arrays (busy 1280x720 frame: the same pixels, about 5 % less CPU).
# Characters are drawn afresh every frame rather than blitted from cached renders keyed on their
# drawing inputs: in bench/view.py's busy scene no figure's points repeat from one frame to the
# next, and even rounded to whole pixels a pose recurs in only 15-50 % of frames, while a hit
# still blits the figure's whole rectangle with per-pixel alpha (a 221 px square costs ~0.1 ms
# with a cold cache here) and a miss draws the figure twice (on black and on white, for its
# coverage) and extracts it: more lost on misses than won on hits.
_BODY_UV = [(float(u), float(v)) for u, v in REACTOR_BODY]
_EYES_UV = [(float(u), float(v)) for u, v in REACTOR_EYES]


def _mapped(uv: list[tuple[float, float]], m: tuple[float, float, float, float], k: float,
            ox: float, oy: float) -> list[tuple[float, float]]:
    """Local points ``uv`` through the row-vector map ``m`` (``p @ M``), times ``k``, plus
    (``ox``, ``oy``) pixels."""
    a, b, c, d = m[0] * k, m[1] * k, m[2] * k, m[3] * k
    return [(u * a + v * c + ox, u * b + v * d + oy) for u, v in uv]


def draw_reactor(surf: pygame.Surface, c: CharacterState, pose: Pose) -> pygame.Rect | None:
    """The default character: an egg-shaped creature, nose along its heading, on a soft glow,
    with a lighter belly and two eyes. Returns the rectangle it touched."""
    L = c.size * pose.ppm * pose.scale
    if L < 2:
        return None
    # One 2x2 map per layer (local units -> pixels: squash, size, heading), one product each.
    ca, sa = math.cos(pose.angle), math.sin(pose.angle)
    s00, s01, s10, s11 = _squash(pose)
    M = ((s00 * ca - s01 * sa) * L, (s00 * sa + s01 * ca) * L,
         (s10 * ca - s11 * sa) * L, (s10 * sa + s11 * ca) * L)
    rb = pose.breath ** 0.5
    A = (M[0] * rb, M[1] * rb, M[2] * pose.breath, M[3] * pose.breath)   # breathing body
    cx, cy = pose.center
    # The glow keeps the grown-up size while the body grows in (its strength fades in): one
    # cached light per character instead of a new one every few frames of a fade.
    touched = P.glow(surf, pose.center, 0.8 * c.size * pose.ppm, pose.color,
                     0.36 * pose.alpha * pose.light)
    # Little feet peeking out at the sides, stepping while it moves.
    step = 0.1 * min(1.0, (pose.stretch - 1.0) / 0.1) * math.sin(pose.phase)
    foot = pose.body(0.62)
    for fx, fy in ((-0.05 + step, 0.3), (-0.05 - step, -0.3)):
        fx, fy = fx * L, fy * L
        P.disc(surf, foot, (fx * ca - fy * sa + cx, fx * sa + fy * ca + cy), 0.085 * L)
    P.polygon(surf, pose.body(0.72), _mapped(_BODY_UV, A, 1.06, cx, cy + 0.04 * L))
    P.polygon(surf, pose.body(), _mapped(_BODY_UV, A, 1.0, cx, cy))
    P.polygon(surf, fade(lighten(pose.color, 0.35), pose.alpha),
              _mapped(_BODY_UV, M, 0.55, cx + 0.05 * (M[0] - M[2]), cy + 0.05 * (M[1] - M[3])))
    eyes(surf, pose, _mapped(_EYES_UV, M, 1.0, cx, cy), 0.1 * L)
    pad = 0.9 * L * pose.stretch
    x0, y0, x1, y1 = cx - pad - 1, cy - pad - 1, cx + pad + 2, cy + pad + 2
    return P.union([touched, pygame.Rect(int(x0), int(y0), int(x1 - x0) + 1, int(y1 - y0) + 1)])


def _chains(bones: Sequence[tuple[int, int]]) -> list[list[int]]:
    """Bones grouped into runs of consecutive bones (b of one is a of the next)."""
    out: list[list[int]] = []
    for a, b in bones:
        if out and out[-1][-1] == a:
            out[-1].append(b)
        else:
            out.append([a, b])
    return out


def _spine(bones: Sequence[tuple[int, int]]) -> list[int]:
    """The figure's spine: from the first bone's parent, always on to the first-listed child
    (a humanoid's pelvis -> chest -> neck -> head, a creature's hips -> shoulders -> nose)."""
    children: dict[int, list[int]] = {}
    for a, b in bones:
        children.setdefault(a, []).append(b)
    path = [bones[0][0]]
    while path[-1] in children and len(path) <= len(bones):
        nxt = children[path[-1]][0]
        if nxt in path:
            break
        path.append(nxt)
    return path


def _subtree_sizes(n: int, bones: Sequence[tuple[int, int]]) -> np.ndarray:
    """For each point, how many points hang below it (bones run parent -> child)."""
    size = np.ones(n)
    for a, b in reversed(list(bones)):
        if 0 <= a < n and 0 <= b < n:
            size[a] += size[b]
    return size


def _valid_bones(n: int, bones: Sequence[tuple[int, int]]) -> list[tuple[int, int]]:
    return [(a, b) for a, b in bones if 0 <= a < n and 0 <= b < n and a != b]


_topologies: dict[tuple, tuple] = {}


def topology(n: int, bones: Sequence[tuple[int, int]]) -> tuple:
    """(valid bones in drawing order, spine points, relative thickness per point, spine flags
    per bone) of a figure, computed once per bone set: limbs first, the spine over them."""
    key = (n, tuple(bones))
    topo = _topologies.get(key)
    if topo is None:
        valid = _valid_bones(n, bones)
        if not valid:
            return [], [], np.ones(n), [], [], [], []
        sub = _subtree_sizes(n, valid)
        rel = 0.45 + 0.55 * np.sqrt(sub / sub.max())
        spine = _spine(valid)
        in_spine = set(spine)
        on_spine = [a in in_spine and b in in_spine for a, b in valid]
        order = sorted(range(len(valid)), key=lambda i: (on_spine[i], -sub[valid[i][1]]))
        knots = [i for i in range(n) if sub[i] > 1 and i not in in_spine]
        used = {p for ab in valid for p in ab}
        limb_points = sorted(used - in_spine)
        topo = ([valid[i] for i in order], spine, rel, [on_spine[i] for i in order], knots,
                [i for i in spine if i != spine[-1]], limb_points)
        if len(_topologies) > 256:
            _topologies.clear()
        _topologies[key] = topo
    return topo


def _posed(c: CharacterState, pose: Pose, pts: np.ndarray) -> tuple[np.ndarray, float] | None:
    """A figure's points (pixels) scaled about the pose's centre by its growth and breath, and
    the figure's size in pixels; None when there is nothing finite to draw."""
    if len(pts) == 0 or not math.isfinite(float(pts.sum())):   # NaN or inf anywhere
        return None
    ctr = np.asarray(pose.center)
    return (pts - ctr) * (pose.scale * pose.breath) + ctr, c.size * pose.ppm * pose.scale


def draw_figure(surf: pygame.Surface, c: CharacterState, pose: Pose,
                pts: np.ndarray, head: bool = True) -> pygame.Rect | None:
    """An articulated figure (skeleton, creature, sprite sheet): limbs with thickness and
    joints, the spine (from the first bone, first children on) thickest, a head with eyes at the
    spine's end (unless ``head`` is False). Returns the rectangle it touched."""
    n = len(pts)
    posed = _posed(c, pose, pts)
    if posed is None:
        return None
    pts, fig = posed
    (x0, y0), (x1, y1) = pts.min(axis=0).tolist(), pts.max(axis=0).tolist()
    # The glow's size follows the figure's grown-up size, not its pose or its growing in (its
    # strength fades in): one cached light per figure.
    touched = P.glow(surf, ((x0 + x1) / 2, (y0 + y1) / 2), 0.42 * c.size * pose.ppm + 6, pose.color,
                     0.26 * pose.alpha * pose.light)
    bones, spine, rel, on_spine, *rest = topology(n, c.bones)
    w0 = max(1.5, {"skeleton": 0.03, "sprite": 0.075}.get(c.kind, 0.045) * fig)
    body = pose.body()
    q = pts.tolist()
    if not bones:
        for p in q:
            P.disc(surf, body, p, max(2.0, 0.03 * fig))
        return P.union([touched, P.bounds(pts, max(2.0, 0.03 * fig) + 2)])
    knots, spine_points, limb_points = rest
    w = (w0 * rel).tolist()
    wspine = w0 * (1.25 if c.kind == "skeleton" else 1.0)
    for i in spine_points:
        w[i] = max(w[i], wspine * rel[i])
    dark, light = pose.body(0.68), fade(lighten(pose.color, 0.18), pose.alpha)
    line = pygame.draw.aaline
    for (a, b), sp in zip(bones, on_spine):   # limbs first, the spine over them
        if sp:
            break
        line(surf, dark, q[a], q[b], max(1, int(w[a] + w[b])))
    P.discs(surf, dark, [q[i] for i in limb_points], [w[i] for i in limb_points])  # joints, ends
    if c.kind in ("creature", "sprite") and len(spine) >= 3:
        _torso(surf, body, q[spine[0]], q[spine[-2]], wspine, c.kind == "sprite")
    for (a, b), sp in zip(bones, on_spine):
        if sp:
            line(surf, body, q[a], q[b], max(1, int(w[a] + w[b])))
    P.discs(surf, body, [q[i] for i in spine_points], [w[i] for i in spine_points])
    big = [i for i in knots if w[i] > 3]       # a lighter knot where a limb bends
    P.discs(surf, light, [q[i] for i in big], [w[i] * 0.45 for i in big])
    if head:
        _head(surf, c, pose, q, spine, fig)
    pad = wspine + 0.08 * fig + 2
    x0, y0, x1, y1 = x0 - pad - 1, y0 - pad - 1, x1 + pad + 2, y1 + pad + 2
    return P.union([touched, pygame.Rect(int(x0), int(y0), int(x1 - x0) + 1, int(y1 - y0) + 1)])


def _torso(surf: pygame.Surface, color: Color, a: Sequence[float], b: Sequence[float], w: float,
           plump: bool) -> None:
    """A filled body between the spine's first point and the neck: a slim one for a creature,
    a plump one for a bird."""
    (ax, ay), (bx, by) = a, b
    dx, dy = bx - ax, by - ay
    length = math.hypot(dx, dy)
    if length < 2:
        return
    rx = 0.5 * length + w
    ry = max(w * 1.6, 0.3 * rx if plump else w * 1.3)
    P.ellipse(surf, color, ((ax + bx) / 2, (ay + by) / 2), rx, ry, math.atan2(dy, dx), 20)


def _head(surf: pygame.Surface, c: CharacterState, pose: Pose, pts: Sequence[Sequence[float]],
          spine: list[int], fig: float) -> None:
    """A head at the spine's end, facing along the last spine bone, eyes looking along the gaze."""
    if len(spine) < 2:
        return
    (hx, hy), (px, py) = pts[spine[-1]], pts[spine[-2]]
    dx, dy = hx - px, hy - py
    dn = math.hypot(dx, dy)
    facing = math.atan2(dy, dx) if dn > 1e-6 else pose.angle
    if c.kind == "skeleton":   # the last spine bone runs from the neck to the top of the head
        ox, oy = (hx + px) / 2, (hy + py) / 2
        r = max(0.5 * dn, 0.06 * fig)
    else:
        ox, oy = hx - dx * 0.35, hy - dy * 0.35
        r = 0.06 * fig
    P.disc(surf, pose.body(), (ox, oy), max(2.5, r))
    sx, sy = -math.sin(facing), math.cos(facing)
    if c.kind == "skeleton":
        # Seen from the side or above: the eyes sit on the head, turned toward the gaze.
        lx, ly = 0.35 * r * math.cos(pose.gaze), 0.35 * r * math.sin(pose.gaze)
        ex, ey, k = ox + lx, oy + ly, 0.33 * r
    else:
        fx, fy = math.cos(facing), math.sin(facing)
        ex, ey, k = ox + fx * 0.25 * r, oy + fy * 0.25 * r, 0.5 * r
    eyes(surf, pose, ((ex + sx * k, ey + sy * k), (ex - sx * k, ey - sy * k)), max(1.6, 0.32 * r))


def _loops(bones: Sequence[tuple[int, int]]) -> list[tuple[list[int], bool]]:
    """Runs of bones as (points, closed): a run is closed when it ends where it began."""
    out = []
    for ch in _chains(bones):
        closed = len(ch) > 3 and ch[0] == ch[-1]
        out.append((ch[:-1] if closed else ch, closed))
    return out


@functools.lru_cache(maxsize=64)
def _face_loops(n: int, bones: tuple) -> list[tuple[list[int], bool]]:
    """A face's loops (see :func:`_loops`), found once per bone set."""
    return _loops(_valid_bones(n, bones))


def draw_face(surf: pygame.Surface, c: CharacterState, pose: Pose,
              pts: np.ndarray) -> pygame.Rect | None:
    """A face: its first closed loop is the head (filled, on a glow), smaller closed loops are
    eyes (white with pupils looking along the gaze, blinking) or the mouth (dark), open strokes
    are brows and nose drawn thick. Returns the rectangle it touched."""
    n = len(pts)
    posed = _posed(c, pose, pts)
    if posed is None:
        return None
    pts, fig = posed
    loops = _face_loops(n, tuple(c.bones))
    if not loops:
        return None
    touched = P.bounds(pts, 0.06 * fig + 2)
    ink = fade(INK, pose.alpha)
    stroke = max(1.5, 0.022 * fig)
    first = True
    gx, gy = math.cos(pose.gaze), math.sin(pose.gaze)
    ux, uy = -math.sin(pose.angle), math.cos(pose.angle)     # up the face
    xy = pts.tolist()     # a face's loops have a few points each: plain floats, not tiny arrays
    for idx, closed in loops:
        q = [xy[i] for i in idx]
        if not closed:                                               # brows, nose
            for a, b in zip(q[:-1], q[1:]):
                P.limb(surf, ink, a, b, stroke * 0.8)
            continue
        k = len(q)
        mx, my = sum(x for x, _ in q) / k, sum(y for _, y in q) / k
        if first:                                                    # the head
            touched = P.union([touched, P.glow(
                surf, (mx, my), 0.62 * c.size * pose.ppm + 6, pose.color,
                0.32 * pose.alpha * pose.light)])
            P.polygon(surf, pose.body(0.7),
                      [((x - mx) * 1.04 + mx, (y - my) * 1.04 + my) for x, y in q])
            P.polygon(surf, pose.body(), q)
            first = False
            continue
        xs, ys = [x for x, _ in q], [y for _, y in q]
        w, h = max(xs) - min(xs), max(ys) - min(ys)
        if abs(w - h) < 0.8 * max(w, h) and k <= 10:                 # an eye
            shut = 1 - pose.blink
            lid = []
            for x, y in q:
                rx, ry = x - mx, y - my
                along = (rx * ux + ry * uy) * shut
                lid.append((rx - along * ux + mx, ry - along * uy + my))
            P.polygon(surf, fade(EYE_WHITE, pose.alpha), lid)
            if pose.blink > 0.45:
                d = 0.3 * max(w, h)
                P.disc(surf, ink, (mx + gx * d, my + gy * d), 0.45 * min(w, h) + 1)
        else:                                                        # the mouth
            P.polygon(surf, ink, q)
    return touched


@functools.lru_cache(maxsize=64)
def hybrid_parts(n: int, bones: tuple) -> tuple[int, tuple, tuple] | None:
    """A hybrid's parts (a body with a face riding on it, MOP section 3): (index of the face's
    first point, the body's bones, the face's bones numbered from 0). The body is every point
    joined to the first bone's; the face's loops follow it. None when there is no such split."""
    valid = _valid_bones(n, bones)
    if not valid:
        return None
    body = {valid[0][0]}
    grew = True
    while grew:
        grew = False
        for a, b in valid:
            if (a in body) != (b in body):
                body.update((a, b))
                grew = True
    k = max(body) + 1
    if k >= n or any(a < k <= b or b < k <= a for a, b in valid):
        return None
    return (k, tuple((a, b) for a, b in valid if b < k),
            tuple((a - k, b - k) for a, b in valid if a >= k))


def draw_hybrid(surf: pygame.Surface, c: CharacterState, pose: Pose,
                pts: np.ndarray) -> pygame.Rect | None:
    """A hybrid character: its body drawn as a creature's (no head of its own) and its face
    drawn as a face where the head would be. ``pts``: every point in pixels. Returns the
    rectangle it touched."""
    parts = hybrid_parts(len(pts), tuple(c.bones))
    if parts is None or c.points is None:
        return draw_figure(surf, c, pose, pts)
    k, body_bones, face_bones = parts
    face_m = np.asarray(c.points)[k:]
    if not np.all(np.isfinite(face_m)):
        return None
    body = replace(c, kind="creature", bones=body_bones, points=None, hint_points=None)
    face = replace(c, kind="face", bones=face_bones, points=None, hint_points=None,
                   size=float(np.ptp(face_m, axis=0).max()))
    return P.union([draw_figure(surf, body, pose, pts[:k], head=False),
                    draw_face(surf, face, pose, pts[k:])])
