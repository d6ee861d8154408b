"""Each character kind drawn whole by one compiled call (numba): the default reactor, an
articulated figure (skeleton, creature, sprite sheet) and a face, with their eyes.

A figure's ~50 limbs, joints, torso, head and eyes, a face's loops, a reactor's feet, body and
eyes cost one call instead of a Python-level drawing call each (the busy frame's time was per
call, spread over ~4,900 of them); :mod:`tabletop.drawing.characters` computes each character's
pose, geometry and colours and calls these through :func:`tabletop.drawing.raster.draw`.
"""

from __future__ import annotations

import math

import numpy as np

from tabletop.drawing.discs import disc
from tabletop.drawing.kernel_cache import kernel
from tabletop.drawing.limbs import capsule, cone
from tabletop.drawing.polygons import ellipse, polygon

SKELETON, CREATURE, SPRITE, OTHER = 0, 1, 2, 3     # figure kinds (``figure``'s ``kind``)
# A sprite sheet's head (the MOP example's bird seen from above): its radius, of the figure's
# size, and its eyes' radius, of the head's. At a creature's 0.06 and 0.32 the bird's eyes were
# 2.4 px at 1280x720 (a 0.15 m bird), white specks with a pupil of a pixel.
BIRD_HEAD, BIRD_EYE = 0.09, 0.42
HEAD, FEATURES = 1, 2                              # a face's parts (``face``'s ``parts``)
# A head seen by a camera (a touch-posed humanoid): its eyes lie EYE_YAW radians to either side
# of where it faces, on a sphere EYE_R times the head's radius (from the front they lie as a
# figure's seen from above: 0.5 radii apart from its middle), and show while they face the
# viewer by more than EYE_SEEN (the cosine to the view). The example's humanoid at elevation 15
# (eye pixels at 1280x720): two from the front (143) and at azimuth 45 (123: the far one faces
# it by 0.12, hidden at 0.15), one in profile (70), none from 135 or behind; two (134-143) at
# every azimuth before.
EYE_YAW, EYE_R, EYE_SEEN = 0.6, 0.885, 0.05


@kernel
def _eye(pix: np.ndarray, fmt: np.ndarray, cx: float, cy: float, r: float, blink: float,
         gx: float, gy: float, angle: float, white: int, ink: int,
         spans: np.ndarray | None = None) -> None:
    if blink > 0.97:
        disc(pix, fmt, cx, cy, r + 0.5, white, spans)
    else:
        ellipse(pix, fmt, cx, cy, r + 0.5, max(0.6, r * blink) + 0.5, angle + math.pi / 2, 14,
                white, spans)
    if blink > 0.45:
        px, py = cx + gx * r * 0.42, cy + gy * r * 0.42
        disc(pix, fmt, px, py, r * 0.52 + 0.5, ink, spans)
        disc(pix, fmt, px - 0.125 * r, py - 0.175 * r, max(1.0, r * 0.16) + 0.5, white, spans)


@kernel
def eyes(pix: np.ndarray, fmt: np.ndarray, x1: float, y1: float, x2: float, y2: float,
         r: float, blink: float, gaze: float, angle: float, white: int, ink: int,
         spans: np.ndarray | None = None) -> None:
    """Two eyes of radius ``r`` px at (x1, y1) and (x2, y2): white, a dark pupil turned along
    ``gaze`` (screen radians) with a glint, lids closing with ``blink`` (opening 0..1) across
    ``angle`` (``spans``: :func:`figure`)."""
    if r < 1.5:
        return
    gx, gy = math.cos(gaze), math.sin(gaze)
    _eye(pix, fmt, x1, y1, r, blink, gx, gy, angle, white, ink, spans)
    _eye(pix, fmt, x2, y2, r, blink, gx, gy, angle, white, ink, spans)


@kernel
def _mapped(uv: np.ndarray, a: float, b: float, c: float, d: float, k: float, ox: float,
            oy: float) -> tuple[np.ndarray, np.ndarray]:
    n = uv.shape[0]
    xs, ys = np.empty(n), np.empty(n)
    for i in range(n):
        u, v = uv[i, 0], uv[i, 1]
        xs[i] = (u * a + v * c) * k + ox
        ys[i] = (u * b + v * d) * k + oy
    return xs, ys


@kernel
def reactor(pix: np.ndarray, fmt: np.ndarray, uv: np.ndarray, eyes_uv: np.ndarray,
            m: np.ndarray, breath: float, cx: float, cy: float, L: float, ca: float, sa: float,
            step: float, foot: int, dark: int, body: int, belly: int, blink: float,
            gaze: float, angle: float, white: int, ink: int) -> None:
    """The default character around (cx, cy) px, ``L`` px long: two stepping feet, a shadowed
    egg body breathing (``breath``), a lighter belly and two eyes. ``m``: the 2x2 row-vector map
    (4 floats) of its squash and stretch, heading and length; ``uv``, ``eyes_uv``: its outline
    and eyes in body lengths."""
    for fx, fy in ((-0.05 + step, 0.3), (-0.05 - step, -0.3)):
        fx, fy = fx * L, fy * L
        disc(pix, fmt, fx * ca - fy * sa + cx, fx * sa + fy * ca + cy, 0.085 * L + 0.5, foot)
    rb = math.sqrt(breath)
    a, b, c, d = m[0] * rb, m[1] * rb, m[2] * breath, m[3] * breath
    xs, ys = _mapped(uv, a, b, c, d, 1.06, cx, cy + 0.04 * L)
    polygon(pix, fmt, xs, ys, len(xs), dark)
    xs, ys = _mapped(uv, a, b, c, d, 1.0, cx, cy)
    polygon(pix, fmt, xs, ys, len(xs), body)
    xs, ys = _mapped(uv, m[0], m[1], m[2], m[3], 0.55, cx + 0.05 * (m[0] - m[2]),
                     cy + 0.05 * (m[1] - m[3]))
    polygon(pix, fmt, xs, ys, len(xs), belly)
    xs, ys = _mapped(eyes_uv, m[0], m[1], m[2], m[3], 1.0, cx, cy)
    eyes(pix, fmt, xs[0], ys[0], xs[1], ys[1], 0.1 * L, blink, gaze, angle, white, ink)


@kernel
def figure(pix: np.ndarray, fmt: np.ndarray, q: np.ndarray, rel: np.ndarray, tp: np.ndarray,
           kind: int, w0: float, wspine: float, fig: float, head: bool, dark: int, body: int,
           light: int, angle: float, gaze: float, blink: float, white: int, ink: int,
           vx: float, vy: float, vz: float, spans: np.ndarray | None = None) -> None:
    """An articulated figure (points ``q`` px, topology ``tp`` from :func:`pack_topology`):
    limbs and their joints in the ``dark`` shade, a torso for a creature or bird, the spine and
    its joints over them, lighter knots where limbs bend, and a head with eyes at the spine's
    end (unless ``head`` is False). Half-widths are ``w0`` px times each point's relative
    thickness ``rel``, at least ``wspine`` times it on the spine but its end. ``fig``: its size
    in px; (``vx``, ``vy``, ``vz``): where its head faces as a camera sees it (px on screen per
    unit, then toward the viewer; NaN: seen from above). ``spans`` (rows x (first, last) px,
    or None): each row's pixels drawn marked in it (:func:`tabletop.drawing.blend.mark`: a
    hinted pose's outline walks only them, :mod:`tabletop.drawing.outline_kernel`)."""
    nb, nl, nlp, nsp, nk, ns = tp[0], tp[1], tp[2], tp[3], tp[4], tp[5]
    o = 6
    ol = o + 2 * nb
    osp = ol + nlp
    ok = osp + nsp
    os_ = ok + nk
    spined = np.zeros(q.shape[0], np.bool_)
    for j in range(ns):
        spined[tp[os_ + j]] = True
    w = np.empty(q.shape[0])
    for i in range(q.shape[0]):
        w[i] = w0 * rel[i]
    for j in range(ns - 1):
        i = tp[os_ + j]
        w[i] = max(w[i], wspine * rel[i])
    # Limbs taper from joint to joint, each joint's disc (radius w + 0.5) a round end of the
    # limbs meeting there; a limb's end on the spine (which covers it) is as thick as the limb.
    for k in range(nl):
        a, b = tp[o + 2 * k], tp[o + 2 * k + 1]
        wl = 0.5 * max(1, int(w[a] + w[b]))
        cone(pix, fmt, q[a, 0], q[a, 1], wl if spined[a] else w[a] + 0.5, q[b, 0], q[b, 1],
             wl if spined[b] else w[b] + 0.5, dark, spans)
    if (kind == CREATURE or kind == SPRITE) and ns >= 3:     # the torso along the spine
        s0, s1 = tp[os_], tp[os_ + ns - 2]
        ax, ay, bx, by = q[s0, 0], q[s0, 1], q[s1, 0], q[s1, 1]
        dx, dy = bx - ax, by - ay
        length = math.hypot(dx, dy)
        if length >= 2:
            rx = 0.5 * length + wspine
            ry = max(wspine * 1.6, 0.3 * rx if kind == SPRITE else wspine * 1.3)
            ellipse(pix, fmt, (ax + bx) / 2, (ay + by) / 2, rx, ry, math.atan2(dy, dx), 20,
                    body, spans)
    for k in range(nl, nb):                                  # the spine over them, tapered
        a, b = tp[o + 2 * k], tp[o + 2 * k + 1]
        bx, by, rb = q[b, 0], q[b, 1], w[b] + 0.5
        if head and kind == SKELETON and b == tp[os_ + ns - 1]:
            bx, by = (q[a, 0] + bx) / 2, (q[a, 1] + by) / 2  # ends in the head: no round tip
            rb = 0.5 * max(1, int(w[a] + w[b]))
        cone(pix, fmt, q[a, 0], q[a, 1], w[a] + 0.5, bx, by, rb, body, spans)
    for j in range(nk):                                      # a lighter knot where a limb bends
        i = tp[ok + j]
        if w[i] > 3:
            disc(pix, fmt, q[i, 0], q[i, 1], w[i] * 0.45 + 0.5, light, spans)
    if head and ns >= 2:
        _head(pix, fmt, q, tp[os_ + ns - 1], tp[os_ + ns - 2], kind, fig, body, angle, gaze,
              blink, white, ink, vx, vy, vz, spans)


@kernel
def _head(pix: np.ndarray, fmt: np.ndarray, q: np.ndarray, h: int, p: int, kind: int,
          fig: float, body: int, angle: float, gaze: float, blink: float, white: int,
          ink: int, vx: float, vy: float, vz: float, spans: np.ndarray | None = None) -> None:
    """A head at the spine's end ``h`` (``p`` before it), facing along that last bone, eyes
    looking along the gaze; seen by a camera (``vz`` not NaN, :func:`figure`), its eyes where
    they face the viewer (:func:`_seen_eyes`)."""
    hx, hy, px, py = q[h, 0], q[h, 1], q[p, 0], q[p, 1]
    dx, dy = hx - px, hy - py
    dn = math.hypot(dx, dy)
    facing = math.atan2(dy, dx) if dn > 1e-6 else angle
    if kind == SKELETON:   # the last spine bone runs from the neck to the top of the head
        ox, oy = (hx + px) / 2, (hy + py) / 2
        r = max(0.5 * dn, 0.06 * fig)
    else:   # a bird seen from above has a round head, its eyes much of it
        ox, oy = hx - dx * 0.35, hy - dy * 0.35
        r = (BIRD_HEAD if kind == SPRITE else 0.06) * fig
    disc(pix, fmt, ox, oy, max(2.5, r) + 0.5, body, spans)
    er = max(1.6, (BIRD_EYE if kind == SPRITE else 0.32) * r)
    if not math.isnan(vz):
        _seen_eyes(pix, fmt, ox, oy, r, math.cos(facing), math.sin(facing), vx, vy, vz, er,
                   blink, angle, white, ink, spans)
        return
    sx, sy = -math.sin(facing), math.cos(facing)
    if kind == SKELETON:   # seen from the side or above: the eyes turned toward the gaze
        ex, ey, k = ox + 0.35 * r * math.cos(gaze), oy + 0.35 * r * math.sin(gaze), 0.33 * r
    else:
        ex, ey, k = ox + math.cos(facing) * 0.25 * r, oy + math.sin(facing) * 0.25 * r, 0.5 * r
    eyes(pix, fmt, ex + sx * k, ey + sy * k, ex - sx * k, ey - sy * k, er, blink, gaze, angle,
         white, ink, spans)


@kernel
def _seen_eyes(pix: np.ndarray, fmt: np.ndarray, ox: float, oy: float, r: float, ux: float,
               uy: float, vx: float, vy: float, vz: float, er: float, blink: float,
               angle: float, white: int, ink: int, spans: np.ndarray | None = None) -> None:
    """The eyes of a round head (centre ``ox``, ``oy``, radius ``r`` px, up along ``ux``,
    ``uy``) facing (``vx``, ``vy``) on screen and ``vz`` toward the viewer: each where it lies
    on the head as seen, drawn only while it faces the viewer (:data:`EYE_SEEN`), looking
    where the head faces."""
    # the head's side: across its up (on screen) and its facing
    sx, sy, sz = uy * vz, -ux * vz, ux * vy - uy * vx
    n = math.sqrt(sx * sx + sy * sy + sz * sz)
    if r < 1.0 or er < 1.5 or n < 1e-9:
        return
    ca, sa = math.cos(EYE_YAW), math.sin(EYE_YAW) / n
    cx, cy = ox + 0.25 * r * ux, oy + 0.25 * r * uy
    for side in (-1.0, 1.0):
        nx, ny, nz = ca * vx + side * sa * sx, ca * vy + side * sa * sy, ca * vz + side * sa * sz
        if nz > EYE_SEEN:
            # within the head's outline (in profile it lay 0.73 radii out, its white past it)
            k = EYE_R * r
            d = k * math.hypot(nx, ny)
            if d > r - er > 0:
                k *= (r - er) / d
            _eye(pix, fmt, cx + k * nx, cy + k * ny, er, blink, vx, vy, angle, white, ink,
                 spans)


@kernel
def _pupil(xs: np.ndarray, ys: np.ndarray, n: int, mx: float, my: float, gx: float, gy: float,
           r: float, d: float) -> tuple[float, float]:
    """A pupil's radius and its shift along the gaze (``gx``, ``gy``), both px, at most ``r``
    and ``d``, such that it lies inside the eye's white (the convex polygon ``xs``, ``ys``
    about its centre ``mx``, ``my``). A pupil sized by the eye's bounding box and moved a
    share of its width hung out of a face's flat eyes over the skin (the MOP example's face
    looking down at a puck: ~60 px of ink outside each white)."""
    inner = 1e9
    for j in range(n):            # the white's inscribed radius: its nearest edge
        k = (j + 1) % n
        ex, ey = xs[k] - xs[j], ys[k] - ys[j]
        ln = math.sqrt(ex * ex + ey * ey)
        if ln > 1e-9:
            inner = min(inner, abs((xs[j] - mx) * ey - (ys[j] - my) * ex) / ln)
    r = max(1.0, min(r, 0.7 * inner))
    for j in range(n):            # each edge the gaze runs toward bounds the shift
        k = (j + 1) % n
        ex, ey = xs[k] - xs[j], ys[k] - ys[j]
        ln = math.sqrt(ex * ex + ey * ey)
        if ln <= 1e-9:
            continue
        nx, ny = ey / ln, -ex / ln
        h = (xs[j] - mx) * nx + (ys[j] - my) * ny
        if h < 0.0:               # (the outward normal, whichever way the loop winds)
            nx, ny, h = -nx, -ny, -h
        toward = nx * gx + ny * gy
        if toward > 1e-6:
            d = min(d, (h - r - 0.5) / toward)
    return r, max(0.0, d)


@kernel
def face(pix: np.ndarray, fmt: np.ndarray, q: np.ndarray, lp: np.ndarray, stroke: float,
         shadow: int, body: int, white: int, ink: int, blink: float, gaze: float,
         angle: float, parts: int, spans: np.ndarray | None = None) -> None:
    """A face from its loops (``lp`` from :func:`pack_loops`, points ``q`` px): the first closed
    loop is the head (on a ``shadow`` rim), smaller round closed loops are eyes (lids closing
    with ``blink`` across ``angle``, pupils looking along ``gaze``), other closed loops the
    mouth, open strokes (brows, nose) ``stroke`` px thick. ``parts``: :data:`HEAD` (the head
    alone), :data:`FEATURES` (all but the head) or both (their sum); ``spans``: as
    :func:`figure`'s."""
    gx, gy = math.cos(gaze), math.sin(gaze)
    ux, uy = -math.sin(angle), math.cos(angle)     # up the face
    first = True
    for k in range(lp[0]):
        st, n, closed = lp[1 + 3 * k], lp[2 + 3 * k], lp[3 + 3 * k]
        if not closed:                                           # brows, nose
            if not parts & FEATURES:
                continue
            w = stroke * 0.8
            width = max(1, int(2 * w + 0.5))
            for j in range(n - 1):
                a, b = lp[st + j], lp[st + j + 1]
                capsule(pix, fmt, q[a, 0], q[a, 1], q[b, 0], q[b, 1],
                        w + 0.5 if width > 2 else 0.5 * width, ink, spans)
            continue
        xs, ys = np.empty(n), np.empty(n)
        for j in range(n):
            xs[j], ys[j] = q[lp[st + j], 0], q[lp[st + j], 1]
        mx, my = xs.mean(), ys.mean()
        if first:                                                # the head
            if parts & HEAD:
                polygon(pix, fmt, (xs - mx) * 1.04 + mx, (ys - my) * 1.04 + my, n, shadow,
                        spans)
                polygon(pix, fmt, xs, ys, n, body, spans)
            first = False
            continue
        if not parts & FEATURES:
            break
        w, h = xs.max() - xs.min(), ys.max() - ys.min()
        if abs(w - h) < 0.8 * max(w, h) and n <= 10:             # an eye
            shut = 1.0 - blink
            lx, ly = np.empty(n), np.empty(n)
            for j in range(n):
                rx, ry = xs[j] - mx, ys[j] - my
                along = (rx * ux + ry * uy) * shut
                lx[j], ly[j] = rx - along * ux + mx, ry - along * uy + my
            polygon(pix, fmt, lx, ly, n, white, spans)
            if blink > 0.45:
                r, d = _pupil(lx, ly, n, mx, my, gx, gy, 0.45 * min(w, h) + 1.5,
                              0.3 * max(w, h))
                disc(pix, fmt, mx + gx * d, my + gy * d, r, ink, spans)
        else:                                                    # the mouth
            polygon(pix, fmt, xs, ys, n, ink, spans)

