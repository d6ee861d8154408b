"""The projector view (pygame): the table, the pucks and the characters drawn under them.

:class:`Renderer` draws one Frame onto any surface (pure drawing, tested offscreen);
:class:`ProjectorView` is the sink that owns the window (or the headless dummy display), turns
keys into operator commands, saves snapshots and shows the operator overlay.

Keys: Esc or closing the window ends the run; F1 or O toggles the overlay; R, K, X, Tab and A send
``designer.record``, ``designer.keep``, ``designer.discard``, ``designer.next`` and
``designer.assign`` to the engines.
"""

from __future__ import annotations

import logging
import math
import os
import threading
from pathlib import Path
from typing import Any, Callable, Sequence

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import numpy as np  # noqa: E402
import pygame  # noqa: E402

from calibration.transforms import apply_homography, fitted_rectangle  # noqa: E402
from tabletop.frames import CharacterState, Frame, Puck  # noqa: E402
from tabletop.loop import CommandQueue, LoopStats  # noqa: E402

log = logging.getLogger("tabletop")

BACKGROUND = (12, 12, 16)
TABLE = (28, 32, 40)
GRID = (40, 46, 56)
PUCK_COLORS = [(70, 160, 255), (255, 90, 90), (90, 220, 120), (240, 200, 60), (190, 110, 255),
               (60, 220, 220), (255, 140, 40), (230, 230, 230)]
HEADING = (255, 255, 255)
OVERLAY_REFRESH_S = 0.25

KEY_COMMANDS = {pygame.K_r: "designer.record", pygame.K_k: "designer.keep",
                pygame.K_x: "designer.discard", pygame.K_TAB: "designer.next",
                pygame.K_a: "designer.assign"}

# Reactor body in units of its size, nose along +x.
BODY = np.array([(0.55, 0.0), (0.25, 0.27), (-0.3, 0.3), (-0.5, 0.0), (-0.3, -0.3), (0.25, -0.27)])
EYES = np.array([(0.22, 0.12), (0.22, -0.12)])


def puck_color(puck_id: int) -> tuple[int, int, int]:
    """The drawing colour of a puck id."""
    return PUCK_COLORS[puck_id % len(PUCK_COLORS)]


class TableToScreen:
    """Maps table metres to projector pixels with a 3x3 homography: the calibration's
    ``table_to_projector`` when there is one (keystone and all).

    Without a calibration the table is fitted into the window with ``margin`` pixels around it,
    x to the right and y up (the table seen from above).
    """

    def __init__(self, table: tuple[float, float], size: tuple[int, int], margin: int = 24,
                 homography: np.ndarray | None = None) -> None:
        if homography is None:
            homography = fitted_rectangle(table, size, margin)
        self.H = np.asarray(homography, dtype=float)

    def points(self, xy: np.ndarray) -> np.ndarray:
        """(N, 2) table metres -> (N, 2) pixels."""
        return apply_homography(self.H, xy)

    def point(self, x: float, y: float) -> tuple[float, float]:
        p = self.points(np.array([[x, y]]))[0]
        return float(p[0]), float(p[1])

    def scale_at(self, x: float, y: float) -> float:
        """Pixels per metre near (x, y)."""
        a, b = self.points(np.array([[x, y], [x + 0.01, y]]))
        return float(np.hypot(*(b - a)) / 0.01)

    def angle_at(self, x: float, y: float, heading: float) -> float:
        """The on-screen direction (rad, counter-clockwise as seen) of table ``heading`` at
        (x, y): a projector's homography may turn or mirror the table."""
        a, b = self.points(np.array([[x, y], [x + 0.01 * math.cos(heading),
                                              y + 0.01 * math.sin(heading)]]))
        return math.atan2(-(b[1] - a[1]), b[0] - a[0])


def body_polygon(c: CharacterState, shape: np.ndarray) -> np.ndarray:
    """A shape in units of the character's size, rotated to its heading and placed on the table."""
    ca, sa = math.cos(c.heading), math.sin(c.heading)
    rot = np.array([[ca, -sa], [sa, ca]])
    return shape * c.size @ rot.T + (c.x, c.y)


class Renderer:
    """Draws frames: table, characters (under the pucks), pucks with heading, optional overlay."""

    def __init__(self, table: tuple[float, float], size: tuple[int, int], margin: int = 24,
                 homography: np.ndarray | None = None, puck_radius: float = 0.03,
                 sprites: dict[str, Path] | None = None) -> None:
        self.table, self.size = table, size
        self.map = TableToScreen(table, size, margin, homography)
        self.puck_radius = puck_radius
        self._sprites = {name: pygame.image.load(str(p)) for name, p in (sprites or {}).items()}
        self._sprite_cache: dict[tuple[str, int, int], pygame.Surface] = {}
        self._font: pygame.font.Font | None = None
        self._overlay_key: tuple[str, ...] = ()
        self._overlay_imgs: list[pygame.Surface] = []
        self._static: pygame.Surface | None = None

    def _background(self, target: pygame.Surface) -> pygame.Surface:
        if self._static is None or self._static.get_size() != target.get_size():
            s = pygame.Surface(target.get_size())
            s.fill(BACKGROUND)
            w, h = self.table
            corners = self.map.points(np.array([(0, 0), (w, 0), (w, h), (0, h)]))
            pygame.draw.polygon(s, TABLE, corners.tolist())
            for gx in np.arange(0.1, w, 0.1):
                pygame.draw.line(s, GRID, self.map.point(gx, 0), self.map.point(gx, h))
            for gy in np.arange(0.1, h, 0.1):
                pygame.draw.line(s, GRID, self.map.point(0, gy), self.map.point(w, gy))
            self._static = s.convert() if pygame.display.get_surface() else s
        return self._static

    def draw(self, target: pygame.Surface, frame: Frame, overlay: list[str] | None = None) -> None:
        """Draw ``frame`` onto ``target``; ``overlay`` lines are printed top-left when given."""
        target.blit(self._background(target), (0, 0))
        for c in frame.characters:
            self.draw_character(target, c)
        for p in frame.pucks:
            self.draw_puck(target, p)
        if overlay:
            self.draw_overlay(target, overlay)

    def draw_puck(self, target: pygame.Surface, p: Puck) -> None:
        cx, cy = self.map.point(p.x, p.y)
        r = max(3, int(round(self.puck_radius * self.map.scale_at(p.x, p.y))))
        color = puck_color(p.id)
        if p.state == "seen":
            pygame.draw.circle(target, color, (cx, cy), r)
        else:  # coasting: a ring, so an operator sees the prediction
            pygame.draw.circle(target, color, (cx, cy), r, width=max(2, r // 4))
        hx, hy = self.map.point(p.x + 0.7 * self.puck_radius * math.cos(p.angle),
                                p.y + 0.7 * self.puck_radius * math.sin(p.angle))
        pygame.draw.circle(target, HEADING, (hx, hy), max(2, r // 4))

    def draw_character(self, target: pygame.Surface, c: CharacterState) -> None:
        color = c.color if c.valid else tuple(v // 3 for v in c.color)
        if c.points is not None and len(c.points):
            pts = self.map.points(c.points)
            for a, b in c.bones:
                if 0 <= a < len(pts) and 0 <= b < len(pts):
                    pygame.draw.line(target, color, pts[a], pts[b], 3)
            for q in pts:
                pygame.draw.circle(target, color, q, 3)
            return
        if c.name in self._sprites:
            self._draw_sprite(target, c)
            return
        pygame.draw.polygon(target, color, self.map.points(body_polygon(c, BODY)).tolist())
        eye_r = max(2, int(0.07 * c.size * self.map.scale_at(c.x, c.y)))
        for q in self.map.points(body_polygon(c, EYES)):
            pygame.draw.circle(target, (250, 250, 250), q, eye_r)

    def _draw_sprite(self, target: pygame.Surface, c: CharacterState) -> None:
        img = self._sprites[c.name]
        px_size = c.size * self.map.scale_at(c.x, c.y)
        deg = int(round(math.degrees(self.map.angle_at(c.x, c.y, c.heading)) / 2.0)) * 2
        key = (c.name, deg % 360, int(px_size))
        surf = self._sprite_cache.get(key)
        if surf is None:
            zoom = px_size / max(img.get_width(), 1)
            surf = pygame.transform.rotozoom(img, deg, zoom)
            if len(self._sprite_cache) > 2048:
                self._sprite_cache.clear()
            self._sprite_cache[key] = surf
        cx, cy = self.map.point(c.x, c.y)
        target.blit(surf, surf.get_rect(center=(cx, cy)))

    def draw_overlay(self, target: pygame.Surface, lines: Sequence[str]) -> None:
        """Print ``lines`` top-left; the text is rendered again only when the lines change."""
        key = tuple(lines)
        if key != self._overlay_key:
            if self._font is None:
                pygame.font.init()
                self._font = pygame.font.Font(None, 22)
            self._overlay_imgs = [self._font.render(line, True, (235, 235, 235), (0, 0, 0))
                                  for line in lines]
            self._overlay_key = key
        y = 8
        for img in self._overlay_imgs:
            target.blit(img, (8, y))
            y += img.get_height() + 2


def overlay_lines(frame: Frame, stats: LoopStats | None) -> list[str]:
    """The operator overlay: rate, per-stage milliseconds, sources' health, characters' status."""
    start = stats.first_t if stats is not None and stats.first_t is not None else frame.t
    lines = [f"tick {frame.seq}   running {frame.t - start:.1f} s"]
    if stats is not None:
        lines.append(f"{stats.fps():5.1f} fps   skipped {stats.skipped}   errors "
                     f"{sum(stats.errors.values())}")
        for stage, (med, p99) in stats.summary_ms().items():
            lines.append(f"  {stage:<12} {med:6.2f} ms median  {p99:6.2f} ms p99")
    for h in frame.health:
        age = "-" if math.isinf(h.age) else f"{h.age * 1e3:.0f} ms"
        lines.append(f"source {h.name}: {'ok' if h.ok else 'DOWN'}  {h.message}  age {age}")
    for c in frame.characters:
        if c.label:
            lines.append(f"{c.name}: {c.label}")
    return lines


def headless_needed(force: bool) -> bool:
    """True when the view must use SDL's dummy driver: forced, or no display to open."""
    if force:
        return True
    if os.environ.get("SDL_VIDEODRIVER"):
        return os.environ["SDL_VIDEODRIVER"] in ("dummy", "offscreen")
    return not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
                or os.name == "nt" or os.uname().sysname == "Darwin")


class ProjectorView:
    """Sink: the window (or headless display), key commands, overlay and snapshots."""

    def __init__(self, table: tuple[float, float], options: dict[str, Any],
                 stats: LoopStats | None = None, commands: CommandQueue | None = None,
                 stop: threading.Event | None = None, headless: bool = False,
                 homography: np.ndarray | None = None, name: str = "view") -> None:
        self.name = name
        self.stats, self.commands, self.stop = stats, commands, stop
        self.headless = headless_needed(headless or options["headless"])
        if self.headless:
            os.environ["SDL_VIDEODRIVER"] = "dummy"
            log.info("no display: the view runs headless (SDL dummy driver)")
        pygame.display.init()
        size = tuple(options["size"])
        flags = pygame.FULLSCREEN if options["fullscreen"] and not self.headless else 0
        display = options["display"] if options["display"] < pygame.display.get_num_displays() else 0
        self.screen = pygame.display.set_mode(size, flags, display=display)
        pygame.display.set_caption("Tabletop")
        pygame.mouse.set_visible(self.headless or not options["fullscreen"])
        self.renderer = Renderer(table, size, options["margin_px"], homography,
                                 options["puck_radius"], options["sprites"])
        self.show_overlay = bool(options["overlay"])
        self._overlay: list[str] | None = None
        self._overlay_t = -math.inf
        self.overlay_extra: Callable[[], list[str]] | None = None  # more lines, e.g. a check
        self.snapshot_every = float(options["snapshot_every_s"])
        self.snapshot_folder = Path(options["snapshot_folder"])
        self._next_snapshot: float | None = None
        self._saver: threading.Thread | None = None
        self.snapshots = 0

    def consume(self, frame: Frame) -> None:
        self._events()
        overlay = None
        if self.show_overlay:
            # Figures are read by people: refreshing them four times a second is enough and
            # keeps the overlay's cost (percentiles, text) off most ticks.
            if self._overlay is None or frame.t >= self._overlay_t + OVERLAY_REFRESH_S:
                self._overlay, self._overlay_t = overlay_lines(frame, self.stats), frame.t
            overlay = self._overlay + (self.overlay_extra() if self.overlay_extra else [])
        self.renderer.draw(self.screen, frame, overlay)
        pygame.display.flip()
        if self.headless and self.snapshot_every > 0:
            self._snapshot(frame.t)

    def _events(self) -> None:
        for ev in pygame.event.get():
            if ev.type == pygame.QUIT or (ev.type == pygame.KEYDOWN and ev.key == pygame.K_ESCAPE):
                if self.stop is not None:
                    self.stop.set()
            elif ev.type == pygame.KEYDOWN:
                if ev.key in (pygame.K_F1, pygame.K_o):
                    self.show_overlay = not self.show_overlay
                elif ev.key in KEY_COMMANDS and self.commands is not None:
                    self.commands.put(KEY_COMMANDS[ev.key])

    def _snapshot(self, t: float) -> None:
        if self._next_snapshot is None:
            self._next_snapshot = t
        if t < self._next_snapshot:
            return
        self._next_snapshot = t + self.snapshot_every
        if self._saver is not None and self._saver.is_alive():
            return  # the previous snapshot is still being written: never queue them
        path = self.snapshot_folder / f"snapshot-{self.snapshots:05d}.png"
        self.snapshots += 1
        # Encoding a PNG takes tens of milliseconds: copy the pixels now, write in a thread.
        self._saver = threading.Thread(target=save_png, args=(self.screen.copy(), path),
                                       name="snapshot", daemon=True)
        self._saver.start()

    def close(self) -> None:
        if self._saver is not None:
            self._saver.join(timeout=5.0)
        pygame.display.quit()


def save_png(surface: pygame.Surface, path: Path) -> None:
    """Write ``surface`` to ``path`` as PNG atomically (temporary file, then rename)."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.tmp.png")
        pygame.image.save(surface, str(tmp))
        os.replace(tmp, path)
    except (OSError, pygame.error) as exc:
        log.warning("snapshot %s not saved: %s", path, exc)
