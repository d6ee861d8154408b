"""The view's renderer: draws one Frame (the table, the characters with their life, the pucks'
halos and trails, the "one moment" and idle looks, the operator overlay) onto any pygame surface,
with the drawing modules of :mod:`tabletop.drawing`. :class:`tabletop.view.ProjectorView` owns the
window it draws into."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Sequence

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import numpy as np  # noqa: E402
import pygame  # noqa: E402

from tabletop.drawing import characters, dirty, pose_kernel, pucks, screens  # noqa: E402
from tabletop.drawing import outline_kernel, panel_room, see_through  # noqa: E402
from tabletop.drawing import primitives as P  # noqa: E402
from tabletop.drawing import raster  # noqa: E402
from tabletop.drawing.light import (HINT_SHOWN, AddedLight, as_points, hint_label,  # noqa: E402
                                    hint_rim, hinted_pose)
from tabletop.drawing.characters import Pose  # noqa: E402
from tabletop.drawing.life import (TRAIL_S, Lives, Presence,  # noqa: E402
                                   Traces, breath, eyes_open, seed_of, stretch)
from tabletop.drawing.palette import resting, vivid  # noqa: E402
from tabletop.drawing.screens import INVITATIONS, table_surface  # noqa: E402
from tabletop.drawing.sprites import Sprites  # noqa: E402
from tabletop.frames import CharacterState, Frame  # noqa: E402
from tabletop.pointer import POINTER, PointerFingers  # noqa: E402
from tabletop.table_map import TableToScreen  # noqa: E402

IDLE_EMPTY_S = 3.0       # no puck and no touch for this long: nobody plays
IDLE_STILL_S = 30.0      # ... or nothing moved for this long
MOMENT_IN_S, MOMENT_OUT_S = 0.6, 0.4   # the "one moment" screen's fades
LOOK_RANGE_M = 0.6       # a character without a stated target looks at the nearest puck this near
# a mouse finger's ring: its radius (table metres: 9 px at 1280x720 on a 1.2 x 0.8 m table,
# 14 px at 1920x1080, at least 6; its line 2 and 3 px)
FINGER_RING, FINGER_M = (235, 235, 235), 0.0107
# The overlay panel is at most half the window wide (its long lines wrap; a small window's
# panel may take its whole width less 16 px, up to PANEL_MIN_PX): a panel as wide as the
# window, made by one long line (the studio's naming a bad library file), hid the studio's REC
# mark (top-left) or its status line (bottom) in every corner; half as wide, the top-right
# corner is clear of both (1280x720, seen in an Xvfb snapshot).
PANEL_MIN_PX = 480
# Where the overlay panel lies over a character, a puck or the studio's words (a centred
# character in a 640x360 window: the 13-line panel, 370x200 px, is over it in every corner) its
# opacity is lowered by this (of 255): its ground (190) goes to 40, its text to 105. Measured on
# the touch-pose humanoid under it (tests/touch_pose/test_plugin.py): 85% of its light shows
# (the panel drawn alike everywhere: 32%); multiplying its opacity by 0.25 instead showed 83%
# but left the text at a quarter of its light, hard to read over the character.
SEE_THROUGH = 150

# A character drawn at its centre (a reactor, a sprite, the main's ghost) stands at least this many
# of its sizes inside the table's edge: its outline reaches 0.5 (REACTOR_BODY), 0.55 breathing and
# stepping. Engines keep a reactor's centre on the table (Puppet Master clamps it to the table's
# bounds), so one on the edge drawn at its centre would lie half in the margin, off a real table,
# where the projector's light falls on the floor. Pulled in continuously (a clamp), a character
# sliding along the edge moves as it does; its glow may still light the margin, as a puck's ring on
# the edge does (tabletop.drawing.pucks.inside_edge).
BODY_REACH = 0.55


def cameras_down(frame: Frame) -> bool:
    """True when the frame has sources and every one of them is unhealthy, or when a kiosk
    supervisor has marked the frame's ``status`` as ``"one_moment"``."""
    if frame.status == "one_moment":
        return True
    return bool(frame.health) and not any(h.ok for h in frame.health)


class Renderer:
    """Draws frames: the table, the characters with their life (under the pucks), the pucks'
    halos and trails, the "one moment" and idle looks, and the operator overlay.

    The renderer keeps a little memory between frames (who appeared when, pucks' recent paths)
    so that nothing pops; all its times are the frames' ``t``.
    """

    def __init__(self, table: tuple[float, float], size: tuple[int, int], margin: int = 24,
                 homography: np.ndarray | None = None, puck_radius: float = 0.03,
                 sprites: dict[str, Path] | None = None) -> None:
        self.table, self.size = table, size
        # the compiled drawing loaded now, not in the first frame. Deferring it would save a
        # process nothing: the first kernel loaded pays numba's one-off setup (raster's here,
        # 0.34-0.37 CPU s), the others' loads 0.00-0.02 s each
        raster.warm()
        dirty.warm()
        pucks.warm()
        pose_kernel.warm()
        outline_kernel.warm()
        self.map = TableToScreen(table, size, margin, homography)
        self.puck_radius = puck_radius
        self._sprites = Sprites(sprites)   # characters drawn as images
        self._overlay_key: tuple[str, ...] = ()
        self._overlay_cap = 0        # the height (px) the panel was fitted to
        self._overlay_w = (0, 0)     # the window size the panel was made for (px)
        self._overlay_px = screens.PANEL_PX[0]   # its font size (px): smaller in a small window
        self._overlay_img: pygame.Surface | None = None
        self._narrow = panel_room.NarrowPanel()   # the panel wrapped to end before a character
        self._room = panel_room.PanelPlace()   # the overlay panel's corner and narrowing
        self.panel: pygame.Rect | None = None   # where the panel was last drawn (px)
        self._see_through = see_through.SeeThrough()   # its surfaces, kept between frames
        self._keep_clear: list[pygame.Rect] = []   # what the panel should not hide (pixels)
        self._studio_marks: list[pygame.Rect] = []  # what it must not hide: the studio's words
        self._drawn_chars: list[tuple[pygame.Rect, CharacterState]] = []   # (drawn px, state)
        self.studio_mark_right = False   # the studio's REC/TRY mark at the far right corner
        self._labels: dict[int, pygame.Surface] = {}
        self._static: pygame.Surface | None = None
        self._light = AddedLight()   # where hinted poses are drawn, added as light
        self._hint_labels: list[tuple[pygame.Surface, pygame.Rect]] = []   # ... their names
        self._table_px: tuple | None = None   # (map, the table's bounds px): _table_rect
        self.lives = Lives()
        self.traces = Traces()
        self.pointer: PointerFingers = POINTER   # the mouse's fingers, ringed on the table
        self.moment = 0.0            # opacity of the "one moment" screen, 0..1
        self.idle = 0.0              # opacity of the idle look, 0..1
        self._t: float | None = None
        self._last_play_t: float | None = None
        self._last_present_t: float | None = None
        # Dirty rectangles: with ``incremental`` the renderer repaints the table only where the
        # previous frame drew and lists in ``dirty`` what a window must present.
        self.incremental = False
        self.dirty: list[pygame.Rect] = []
        self._drawn: list[pygame.Rect] | None = None   # what the last frame drew (px)
        self._tiles: np.ndarray | None = None           # ... as tiles (tabletop.drawing.dirty)
        self._last_target: pygame.Surface | None = None
        self.invitation = INVITATIONS["puck"]   # the idle look's text (see :func:`invitation`)
        self._invite_at = screens.InvitationPlace()   # ... kept off the characters

    def _corners(self) -> np.ndarray:
        w, h = self.table
        return self.map.points(np.array([(0, 0), (w, 0), (w, h), (0, h)]))

    def _table_rect(self) -> pygame.Rect:
        """The table's bounds in the window (px)."""
        if self._table_px is None or self._table_px[0] is not self.map:
            c = self._corners()
            lo, hi = np.floor(c.min(axis=0)), np.ceil(c.max(axis=0))
            self._table_px = (self.map, pygame.Rect(int(lo[0]), int(lo[1]),
                                                    int(hi[0] - lo[0]), int(hi[1] - lo[1])))
        return self._table_px[1]

    def prepare(self, target: pygame.Surface, parts: Sequence[tuple[str, float]] = ()) -> None:
        """Make what the first frames drawn onto ``target`` would make: the static table (its
        soft light a 480 px glow: 0.15-0.39 s here, the run's first frame that much late) and
        the glows of ``parts`` ((part, size m): :func:`characters.configured_parts`)."""
        self._background(target)
        w, h = self.table
        characters.prepare_glows(parts, self.map.scale_at(w / 2, h / 2))

    def _background(self, target: pygame.Surface) -> pygame.Surface:
        if self._static is None or self._static.get_size() != target.get_size():
            w, h = self.table
            grid = [self.map.point(gx, gy) for gx in np.arange(0.1, w - 1e-9, 0.1)
                    for gy in np.arange(0.1, h - 1e-9, 0.1)]
            s = table_surface(target.get_size(), self._corners(), grid)
            self._static = s.convert() if pygame.display.get_surface() else s
        return self._static

    def draw(self, target: pygame.Surface, frame: Frame, overlay: list[str] | None = None) -> None:
        """Draw ``frame`` onto ``target``; ``overlay`` lines are printed top-left on a panel
        when given (and then, for designers, each puck's id beside its halo)."""
        t = frame.t
        dt = 0.0 if self._t is None else min(max(t - self._t, 0.0), 0.5)
        self._t = t
        bg = self._background(target)
        full = (not self.incremental or self._drawn is None or target is not self._last_target)
        if full:
            target.blit(bg, (0, 0))
        else:
            target.blits([(bg, r, r) for r in self._drawn], doreturn=False)
        down = cameras_down(frame)
        self._update_idle(frame, dt, down)
        step = dt / (MOMENT_IN_S if down else MOMENT_OUT_S)
        self.moment = min(1.0, max(0.0, self.moment + (step if down else -step)))
        if self.idle > 0:
            w, h = self.table
            px, reading = int(0.045 * h * self.map.scale_at(w / 2, h / 2)) + 8, self.map.reading()
            at = self._invite_at([self.map.point(u * w, v * h) for u, v in screens.INVITE_AT],
                                 self.invitation, px, reading,
                                 characters.bodies(frame.characters, self.map))
            screens.idle(target, t, self.idle, self._corners(), self.invitation, at, px, reading)
        drawn: list[pygame.Rect | None] = []
        # what the overlay panel keeps clear of: characters, pucks and the studio's marks and
        # words (its REC seconds and TRY keys were under the panel; the studio's dirty
        # rectangle, the whole window for its recording frame, would hide in every corner)
        self._keep_clear, self._studio_marks, self._drawn_chars = [], [], []
        prs = sorted(self.lives.update(t, frame.characters),
                     key=lambda p: p.state.kind == "studio")   # the studio's marks on top
        self._hint_labels = []
        self._light.begin()
        for p, place in zip(prs, self._places(prs, frame).tolist()):
            r = self._draw_presence(target, p, frame, place)
            drawn.append(r)
            if r is not None and p.state.kind != "studio":
                self._keep_clear.append(r)
                self._drawn_chars.append((r, p.state))
        if self._hint_labels:
            target.blits(self._hint_labels, doreturn=False)
        shown, beyond = pucks.inside_edge(frame.pucks, self.table, self.puck_radius)
        # what went under a puck stays under it: its top (the marker, the hand) is not lit
        pucks.under_pucks(target, bg, shown, beyond, self.map, self.puck_radius,
                          [r for r in drawn if r is not None])
        on_pucks = pucks.draw_pucks(target, self.traces.update(t, shown), self.map,
                                    self.puck_radius, t, TRAIL_S,
                                    self._label if overlay is not None else None, beyond)
        drawn.extend(on_pucks)
        self._keep_clear.extend(r for r in on_pucks if r is not None)
        # the mouse's fingers, held and pinned (a desk, no touch table: a real finger is its
        # own mark), so a finger Shift + click pinned is seen, and where to Shift + click to
        # lift it; known by the ids the pointer holds now, not by an id range: a TUIO
        # tracker counts its session ids up for as long as it runs, past any range
        mouse = {f.id for f in self.pointer.touches()} if frame.touches else set()
        for f in (f for f in frame.touches if f.id in mouse):
            r = max(6, round(FINGER_M * self.map.scale_at(f.x, f.y)))
            drawn.append(pygame.draw.circle(target, FINGER_RING, self.map.point(f.x, f.y), r,
                                            width=max(2, round(r / 4.5))))
        if self.moment > 0:
            screens.one_moment(target, t, self.moment,
                               self.map.point(self.table[0] / 2, self.table[1] / 2),
                               self.map.reading())
        if overlay:
            drawn.append(self.draw_overlay(target, overlay, self._keep_clear,
                                           self._studio_marks))
        size = target.get_size()
        if self.idle > 0 or self.moment > 0:   # whole-table looks: repaint everything next time
            self.dirty, self._drawn, self._tiles = [target.get_rect()], None, None
        else:
            now = dirty.mark(size, drawn)
            self.dirty = [target.get_rect()] if full else dirty.rectangles(now | self._tiles,
                                                                            size, dirty.SLACK)
            self._drawn, self._tiles = dirty.rectangles(now, size), now
        self._last_target = target

    def invalidate(self) -> None:
        """Something was painted over the last frame: present and repaint the whole target."""
        self.dirty, self._drawn, self._tiles = [pygame.Rect((0, 0), self.size)], None, None

    def _update_idle(self, frame: Frame, dt: float, down: bool = False) -> None:
        """The idle look's opacity: in when nobody plays, out while someone does or while
        every camera is down (``down``: the table cannot see a puck, "One moment" shows alone)."""
        t = frame.t
        if self._last_play_t is None:
            self._last_play_t = self._last_present_t = t
        designing = any(c.kind == "studio" and c.action not in (None, "idle", "quiet")
                        for c in frame.characters)   # a designer's take in progress
        present = bool(frame.pucks or frame.touches or frame.streams or designing)
        if present:
            self._last_present_t = t
        moving = (frame.touches or frame.streams or designing
                  or any(math.hypot(p.vx, p.vy) > 0.02 for p in frame.pucks))
        if moving or any(p.id not in self.traces.traces for p in frame.pucks):
            self._last_play_t = t
        nobody = not down and (t - self._last_present_t >= IDLE_EMPTY_S
                               or t - self._last_play_t >= IDLE_STILL_S)
        k = dt / 1.5
        self.idle = min(1.0, max(0.0, self.idle + (k if nobody else -2 * k)))

    def _places(self, prs: Sequence[Presence], frame: Frame | None) -> np.ndarray:
        """Every presence's place on screen (:func:`tabletop.drawing.pose_kernel.places`) in
        one call: what it looks at is its stated target, else the nearest puck within
        :data:`LOOK_RANGE_M` (nothing without a frame)."""
        nan = math.nan
        here = frame is not None
        flat: list[float] = []          # (a flat list: numpy reads it fastest)
        w, h = self.table
        for pr in prs:
            c = pr.state
            look = c.look_at if here and c.look_at is not None else (nan, nan)
            ox, oy = pr.offset(frame.t if here else pr.t)     # gliding after a jump
            x, y = c.x + ox, c.y + oy
            e = BODY_REACH * c.size
            if not (e <= x <= w - e and e <= y <= h - e) and c.points is None \
                    and c.kind != "studio" and 0.0 < e:        # its whole body on the table
                e = min(e, w / 2, h / 2)
                x, y = min(max(x, e), w - e), min(max(y, e), h - e)
            flat += (x, y, c.heading, look[0], look[1],
                     math.atan2(pr.vy, pr.vx) if pr.speed > 1e-3 else nan)
        v = np.array(flat, dtype=np.float64).reshape(-1, 6)
        pk = (np.array([u for p in frame.pucks for u in (p.x, p.y)], dtype=np.float64)
              .reshape(-1, 2) if here else np.zeros((0, 2)))
        out = np.empty((len(prs), pose_kernel.FIELDS))
        pose_kernel.places(v, self.map.H, pk, LOOK_RANGE_M, out)
        return out

    def _pose(self, pr: Presence, t: float, place: Sequence[float]) -> Pose:
        """``pr``'s pose at time ``t`` (s), standing at ``place`` (a row of :meth:`_places`).
        While the "one moment" screen shows, characters fade out with its fade in (the table
        sees nothing then, and a reactor waiting for its main stands at the table's centre, right
        under the ring of lights): the calm screen shows alone, and they fade back with it."""
        c = pr.state
        cx, cy, ppm, angle, looks, look_angle, motion, _ = place
        still = pr.stillness()
        gaze = look_angle if looks else angle + 0.5 * math.sin(0.37 * t + 6.0 * pr.seed) * still
        color = vivid(tuple(c.color)) if c.valid else resting(vivid(tuple(c.color)))
        # (positional: a dataclass made with keywords costs 3-4 times as much)
        return Pose((cx, cy), angle, ppm, pr.alpha(t) * (1.0 - self.moment), pr.scale(t),
                    breath(t, pr.seed, still if c.valid else 1.0), stretch(pr.speed), motion,
                    eyes_open(t, pr.seed), gaze, color, pr.phase)

    def _draw_presence(self, target: pygame.Surface, pr: Presence, frame: Frame | None,
                       place: Sequence[float]) -> pygame.Rect | None:
        c = pr.state
        if c.kind == "studio":           # the studio's countdown, recording mark and status
            from tabletop.studio.draw import draw_studio
            self._studio_marks.extend(draw_studio(target, self, c, self._keep_clear))
            return target.get_rect()
        if not (place[7] and 0.0 <= c.size <= max(self.table)):   # (place: finite, near)
            return None                     # a broken state is not drawn (never raises)
        pose = self._pose(pr, frame.t if frame is not None else pr.t, place)
        if pose.alpha <= 0.01:
            return None
        if c.points is not None and len(c.points):
            hinted = hint = None
            if pr.hint > HINT_SHOWN and pr.hint_points is not None \
                    and len(pr.hint_points) == len(c.points):
                # early feedback: the suspected action's pose, a faint light of the
                # character's own (lively) colour, casting no glow, outlined and named
                ghost = hinted_pose(pose, c.color, pr.hint)
                hinted = self._light.add(target, lambda s, spans: self._draw_points(
                    s, c, ghost, pr.hint_points, spans=spans), hint_rim(target.get_size()),
                    c.name, pr.hint_points, marks=True)
                if hinted is not None and pr.hint_action:
                    label = hint_label(target.get_size(), pr.hint_action, hinted, c.color,
                                       pr.hint, self.map.reading(), self._table_rect())
                    self._hint_labels.append(label)     # drawn over every character
                    hinted = P.union([hinted, label[1]])
                hint = (ghost, pr.hint_points)   # a face's: on the face (draw_face)
            return P.union([hinted, self._draw_points(target, c, pose, c.points, hint)])
        if c.name in self._sprites:
            return self._sprites.draw(target, c, pose, self.map)
        if c.kind == "playback":   # the main take played back in the studio
            return characters.draw_playback(target, pose, self.puck_radius,
                                            self.map.reading())
        return characters.draw_reactor(target, c, pose)

    def _draw_points(self, target: pygame.Surface, c: CharacterState, pose: Pose,
                     xy: np.ndarray, hint: tuple[Pose, np.ndarray] | None = None,
                     spans: np.ndarray | None = None) -> pygame.Rect | None:
        """A character given by points (``xy``: N x 2 table metres), drawn as its kind; a face
        (or a hybrid's) shows ``hint``'s features faintly on it (:func:`draw_face`); each row's
        pixels drawn marked in ``spans`` (a hinted pose's: :class:`AddedLight`)."""
        xy = np.ascontiguousarray(xy, dtype=np.float64).reshape(-1, 2)
        if c.kind == "face":
            return characters.draw_face(target, c, pose, xy, self.map.H, as_points(hint),
                                        spans)
        if c.kind == "hybrid":
            return characters.draw_hybrid(target, c, pose, xy, self.map.H, as_points(hint),
                                          spans)
        return characters.draw_figure(target, c, pose, xy, self.map.H, spans=spans)

    def _label(self, puck_id: int) -> pygame.Surface:
        """A puck's id (:func:`pucks.id_label`) 22 px tall, and larger in a larger window, as
        the overlay's text (:func:`screens.panel_sizes`)."""
        img = self._labels.get(puck_id)
        if img is None:
            px = round(22 * max(1.0, min(self.size) / screens.PANEL_DEEP))
            img = self._labels[puck_id] = pucks.id_label(puck_id, px, self.map.reading())
        return img

    def draw_character(self, target: pygame.Surface, c: CharacterState) -> None:
        """One character fully present (no fade), as it would be drawn standing still."""
        pr = Presence(c, born=-math.inf, t=0.0, seed=seed_of(c.name))
        self._draw_presence(target, pr, None, self._places([pr], None)[0].tolist())

    def draw_overlay(self, target: pygame.Surface, lines: Sequence[str],
                     avoid: Sequence[pygame.Rect] | None = None,
                     must: Sequence[pygame.Rect] | None = None,
                     keep: bool = True) -> pygame.Rect:
        """Print ``lines`` on a translucent panel in a corner of the window (top-left unless it
        would hide what is drawn in ``avoid``, of a character its body (:func:`panel_room.bodies`),
        and another corner hides at most half as much; a pixel of ``must``, the studio's words,
        counts as ``panel_room.MUST_WEIGHT`` of them: a panel over the status line saying the
        disk is full stayed there, other corners having characters; :class:`panel_room.PanelPlace`).
        Where every window corner is over the studio's words, the panel stands in the corner of
        the rows they leave free (in its column), its lines fitted to the tallest such rows: it
        never lies over them when a place clear of them exists (``panel_room.OVER_WORDS``);
        rendered again only when the lines change. Where the panel still lies over ``avoid``,
        it shows them through (:data:`SEE_THROUGH`); over ``must`` it stays dark, so its own
        text stays readable over the studio's. Returns the panel's rectangle. ``avoid`` and
        ``must`` default to what the last :meth:`draw` drew (a snapshot's panel over the view
        drawn without one was always top-left, over a character or puck there). ``keep``
        False: the lines' renders are not remembered (:func:`screens.panel_line`). The panel
        reads upright on the table (:meth:`TableToScreen.reading`); on a table turned a quarter
        round its corner avoids the studio's words by weight alone (their free rows lie across
        its lines)."""
        avoid = self._keep_clear if avoid is None else avoid
        must = self._studio_marks if must is None else must
        W, H = target.get_size()
        # the panel's lines read upright on the table (TableToScreen.reading): on a table
        # turned a quarter round they run along the window's height, which then bounds them
        reading = self.map.reading()
        across, deep = reading.size((W, H))
        width = max(across // 2, min(across - 16, PANEL_MIN_PX))   # the lines wrap within it
        # the rows of each side's column the studio's words leave free: the panel stands in
        # them, no taller than the tallest (in an 800x450 window with the TRY words at the top
        # and the status line at the bottom, every window corner lies over some words),
        # unless they are under a third of the window (a panel of a few lines says too little:
        # it lies over the words, its text kept readable)
        bands = ([panel_room.free_bands(must, x, x + width, 8, H - 8)
                  for x in (8, W - width - 8)]
                 if must and not reading.quarter else [])
        tallest = max((b - a for side in bands for a, b in side), default=deep - 16)
        key, cap = tuple(lines), (tallest if 3 * tallest >= deep else deep - 16)
        sizes = screens.panel_sizes(deep)     # larger in a larger window
        if (W, H) != self._overlay_w:
            self._overlay_px = sizes[0]
        if (key != self._overlay_key or cap != self._overlay_cap or self._overlay_img is None
                or (W, H) != self._overlay_w):
            img, self._overlay_px = screens.fitted_panel(lines, width, cap, self._overlay_px,
                                                         keep=keep, px_sizes=sizes)
            self._overlay_img = reading.turn(img)
            self._overlay_key, self._overlay_cap, self._overlay_w = key, cap, (W, H)
        w, h = self._overlay_img.get_size()
        # the window's corners (0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right), then
        # the same corners of the free rows (4-7: the highest and the lowest free place)
        corners = [(8, 8), (W - w - 8, 8), (8, H - h - 8), (W - w - 8, H - h - 8)]
        if bands:
            tops = [min([a for a, b in side if b - a >= h] or [8]) for side in bands]
            lows = [max([b - h for a, b in side if b - a >= h] or [H - h - 8]) for side in bands]
            corners += [(8, tops[0]), (W - w - 8, tops[1]), (8, lows[0]), (W - w - 8, lows[1])]
        place, img = self._room(
            corners, self._overlay_img, avoid, must, self._drawn_chars, self.map, (W, H),
            (lambda width: self._narrow(lines, width, cap, self._overlay_px, sizes, keep))
            if reading.right == (1, 0) else None, self._t)   # (its lines end on the right)
        self.panel = place
        holes = panel_room.clips(place, avoid)
        if holes:
            # the panel stays where it hides least (a corner that hides less than half as much
            # is needed to move it), so what is left under it shows through: the rectangles
            # are bounding boxes (a glow's, a trail's), so the panel fades over some empty
            # table too; over the studio's words it stays dark, its own text readable
            img = self._see_through(img, holes, panel_room.clips(place, must), SEE_THROUGH)
        return target.blit(img, place)
