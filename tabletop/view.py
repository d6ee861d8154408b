"""The projector view (pygame): the table, the pucks and the characters drawn under them.

:class:`~tabletop.renderer.Renderer` (tabletop/renderer.py) draws one Frame onto any surface
(tested offscreen) with the drawing modules of :mod:`tabletop.drawing`;
:class:`ProjectorView` is the sink that owns the window (or the headless dummy display), turns
keys into operator commands, saves snapshots and shows the operator overlay.

Keys: Esc or closing the window ends the run; F1 or O toggles the overlay; R, K, X, Tab and A send
``designer.record``, ``designer.keep``, ``designer.discard``, ``designer.next`` and
``designer.assign`` to the engines; U, Delete, ] and [ send the studio's ``designer.undo``,
``designer.delete``, ``designer.item_next`` and ``designer.item_previous``; + and - send
``designer.window:+`` and ``:-`` (a MOP character's follower window); F2 types a new name.
"""

from __future__ import annotations

import logging
import math
import os
import re
import threading
import time
from typing import Any, Iterator, Sequence

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import numpy as np  # noqa: E402
import pygame  # noqa: E402

from calibration.transforms import apply_homography  # noqa: E402
from tabletop.drawing import screens  # noqa: E402
from tabletop.drawing.light import HINT_SHOWN  # noqa: E402
from tabletop.drawing.screens import INVITATIONS, invitation  # noqa: E402,F401
from tabletop.display import check_display, start_view_display, window_size  # noqa: E402
from tabletop.frames import Frame  # noqa: E402
from tabletop.loop import CommandQueue, LoopStats  # noqa: E402
from tabletop.loop_stats import LABELS  # noqa: E402
# the renderer and the table mapping, importable from here too (tests, benches)
from tabletop.renderer import Renderer, cameras_down  # noqa: E402,F401
from tabletop.snapshots import Snapshots  # noqa: E402
from tabletop.table_map import TableToScreen  # noqa: E402,F401

log = logging.getLogger("tabletop")

OVERLAY_REFRESH_S = 0.25
OVERLAY_SLICE_S = 0.0005   # the overlay's refresh work per frame: its ~2 ms spread over frames

KEY_COMMANDS = {pygame.K_r: "designer.record", pygame.K_k: "designer.keep",
                pygame.K_x: "designer.discard", pygame.K_TAB: "designer.next",
                pygame.K_a: "designer.assign", pygame.K_u: "designer.undo",
                pygame.K_DELETE: "designer.delete", pygame.K_RIGHTBRACKET: "designer.item_next",
                pygame.K_LEFTBRACKET: "designer.item_previous",
                pygame.K_EQUALS: "designer.window:+", pygame.K_PLUS: "designer.window:+",
                pygame.K_KP_PLUS: "designer.window:+", pygame.K_MINUS: "designer.window:-",
                pygame.K_KP_MINUS: "designer.window:-",
                # the virtual camera of touch-posed characters
                pygame.K_LEFT: "camera.left", pygame.K_RIGHT: "camera.right",
                pygame.K_UP: "camera.up", pygame.K_DOWN: "camera.down"}



def overlay_lines(frame: Frame, stats: LoopStats | None, notes: Sequence[str] = (),
                  likely: dict[str, str] | None = None) -> list[str]:
    """The operator overlay: rate, the parts failing at run time, per-stage milliseconds,
    sources' health (:func:`overlay_steps`), then :func:`panel_tail`."""
    *_, head = overlay_steps(frame, stats)
    return head + panel_tail(frame, notes, likely)


def panel_tail(frame: Frame, notes: Sequence[str] = (),
               likely: dict[str, str] | None = None) -> list[str]:
    """The overlay's lines after its head: the characters' status (:func:`character_lines`)
    and the notices' lines (a refused config edit, the live check)."""
    return character_lines(frame, likely) + list(notes)


def character_lines(frame: Frame, likely: dict[str, str] | None = None) -> list[str]:
    """The overlay's lines of the characters' status (:attr:`CharacterState.label`); one not
    acting whose suspected action ``likely`` names (its hinted pose shown) adds it."""
    likely = likely or {}
    return [f"{c.name}: {c.label}" + (f"   likely: {likely[c.name]}"
                                      if not c.valid and c.name in likely else "")
            for c in frame.characters if c.label]


def suspected(frame: Frame, presences: dict) -> dict[str, str]:
    """Each character's suspected action (its likeliest hint's) while the view shows its
    hinted pose (``presences``: the renderer's, :class:`tabletop.drawing.life.Presence`) and
    it acts on nothing."""
    out = {}
    for c in frame.characters:
        pr = presences.get(c.name)
        if not c.valid and c.hints and pr is not None and pr.hint > HINT_SHOWN:
            out[c.name] = c.hints[0][0]
    return out


_FIGURES = re.compile(r"[-+]?\d[\d.,:]*")


def told(frame: Frame) -> tuple:
    """What the characters' overlay lines say, but for their figures: whether each acts
    (``valid``), its action and its label's words. When it changes (an action begins or
    ends) the panel must say so at once; figures alone (progress, probability) may wait for
    the overlay's refresh, as the stage figures do."""
    return tuple((c.name, c.valid, c.action, _FIGURES.sub("#", c.label))
                 for c in frame.characters if c.label)


def overlay_steps(frame: Frame, stats: LoopStats | None) -> Iterator[list[str] | None]:
    """The head of :func:`overlay_lines` in slices, so that a view can spread the work over
    frames: yields None after each stage's percentiles (the costly part), then the lines."""
    start = stats.first_t if stats is not None and stats.first_t is not None else frame.t
    lines = [f"tick {frame.seq}   running {frame.t - start:.1f} s"]
    if stats is not None:
        fps = stats.fps()   # None on the first tick: no rate yet
        rate = "-.-" if fps is None else f"{fps:.1f}"
        lines.append(f"{rate} fps   skipped {stats.skipped}   errors "
                     f"{sum(stats.errors.values())}")
        # which part fails: the total alone left the operator to search the log for it
        lines += [f"{where} failed {'once' if n == 1 else f'{n} times'} (see the log)"
                  for where, n in sorted(stats.errors.items())]
        for stage in list(stats.samples):
            m = stats.stage_ms(stage)
            yield None
            if m is not None:
                label = LABELS.get(stage, stage)
                # tabs: the panel lines the figures up in columns (screens.panel)
                lines.append(f"  {label:<17}\t{m[0]:6.2f} ms median\t{m[1]:6.2f} ms p99")
    for h in frame.health:
        age = "-" if math.isinf(h.age) else f"{h.age * 1e3:.0f} ms"
        lines.append(f"source {h.name}: {'ok' if h.ok else 'DOWN'}  {h.message}  age {age}")
    yield lines


class ProjectorView:
    """Sink: the window (or headless display), key commands, overlay and snapshots."""

    presents = True   # the loop's capture-to-render latency ends when this sink is done

    def __init__(self, table: tuple[float, float], options: dict[str, Any],
                 stats: LoopStats | None = None, commands: CommandQueue | None = None,
                 stop: threading.Event | None = None, headless: bool = False,
                 homography: np.ndarray | None = None, name: str = "view",
                 invitation: str = INVITATIONS["puck"],
                 parts: Sequence[tuple[str, float]] = ()) -> None:
        self.name = name
        self.stats, self.commands, self.stop = stats, commands, stop
        asked = headless or options["headless"]
        self.headless = start_view_display(asked)
        self._headless_why = ("as asked (--headless or view.headless)" if asked
                              else "as there is no display (DISPLAY is not set)")
        size = tuple(options["size"])
        flags = pygame.FULLSCREEN if options["fullscreen"] and not self.headless else 0
        display = 0 if self.headless else check_display(options["display"])
        opened = size
        if not self.headless and not options["fullscreen"]:
            opened = window_size(size, tuple(pygame.display.get_desktop_sizes()[display]))
        self.screen = pygame.display.set_mode(opened, flags, display=display)
        pygame.display.set_caption("Tabletop")
        pygame.mouse.set_visible(self.headless or not options["fullscreen"])
        self.size = size                 # view.size: the calibration's projector pixels
        given = self.screen.get_size()
        if given != size:
            log.warning("view.size is %dx%d but the window is %dx%d (%s); drawing at %dx%d",
                        *size, *given, "what fits the screen" if opened != size
                        else "what the display gave", *given)
            homography = scaled_homography(homography, size, given)
        self.renderer = Renderer(table, given, options["margin_px"], homography,
                                 options["puck_radius"], options["sprites"])
        self.renderer.incremental = True   # present only what changed (bench/view.py)
        # the table and the characters' glows (``parts``) made before the loop starts, not in
        # its first ticks (drawn 0.28 s late in config.yaml headless, 0.50 s in
        # examples/mop.yaml: the table's 480 px glow; its 3rd-4th frames 12 ms: 7 glows)
        self.renderer.prepare(self.screen, parts)
        self.renderer.invitation = invitation
        self.show_overlay = bool(options["overlay"])
        self._overlay: list[str] | None = None   # the panel's lines: head, characters, notes
        self._head: list[str] = []      # ... rate, stage figures, sources (refreshed)
        self._notes: list[str] = []     # ... the notices' (refreshed)
        self._told: tuple = ()          # what its characters' lines say (:func:`told`)
        self._likely: dict[str, str] = {}   # ... and their hints' actions (:func:`suspected`)
        self._overlay_t = -math.inf
        self._refresh: Iterator[None] | None = None   # the overlay's refresh in progress
        self.snapshots: Snapshots | None = None
        if options["snapshot_every_s"] > 0:
            try:
                self.snapshots = Snapshots(options["snapshot_folder"],
                                           options["snapshot_every_s"], options["snapshot_keep"],
                                           options["snapshot_max_mb"], options["snapshot_per_run"])
            except OSError as exc:
                from tabletop.schema import ConfigError
                why = ("a file, not a folder" if isinstance(exc, FileExistsError)
                       else exc.strerror or exc)   # (mkdir's "File exists" for a file there)
                raise ConfigError(f"view.snapshot_folder: {options['snapshot_folder']}: cannot "
                                  f"be used: {why}") from None
        self.snapshot_overlay = bool(options["snapshot_overlay"])
        self._said_headless = False
        # kiosk: only the service key shows the overlay (and then Esc quits)
        self.kiosk = False
        self.service_key: int | None = None
        self.notices: list = []   # callables returning extra overlay lines (a refused config)
        from tabletop.studio.draw import NamePrompt
        self.prompt = NamePrompt()  # F2: type a new name for the item in play (studio)

    def _notice_lines(self) -> list[str]:
        """The notices' overlay lines now (:attr:`notices`' callables, in order)."""
        return [n for fn in self.notices for n in fn()]

    def consume(self, frame: Frame) -> None:
        if self.headless and not self._said_headless:  # once running, not while starting
            self._said_headless = True
            log.info("the view runs headless (SDL dummy driver), %s", self._headless_why)
        self._events()
        overlay = None
        if self.show_overlay:
            # Figures are read by people: refreshing them four times a second is enough and
            # keeps the overlay's cost (percentiles, text) off most ticks.
            # The refresh (percentiles, text renders) is done in slices of OVERLAY_SLICE_S over
            # the next frames, so that no frame pays for all of it at once.
            now = time.monotonic()  # the wall clock: a stalled camera stops the frames' times
            if self._overlay is None:
                *_, self._head = overlay_steps(frame, self.stats)
                self._notes, self._overlay_t = self._notice_lines(), now
            elif self._refresh is None and now >= self._overlay_t + OVERLAY_REFRESH_S:
                self._refresh, self._overlay_t = self._refreshing(frame), now
            if self._refresh is not None:
                end = time.perf_counter() + OVERLAY_SLICE_S
                for _ in self._refresh:
                    if time.perf_counter() >= end:
                        break
                else:
                    self._refresh, self._overlay = None, None   # its lines take over
            # The characters' lines are this frame's whenever they say something new (an
            # action began or ended) and at each refresh: read from the refresh's first
            # frame, they showed "no action" for up to 16 frames over a figure already
            # acting (a MOP action's start, 60 Hz). Their figures wait for the refresh.
            # A hint's action (MOP's suspected one) changes in about a frame in six: the
            # lines name it as it was at the refresh, and a line whose words change drops it.
            said = told(frame)
            if self._overlay is None:
                self._likely = suspected(frame, self.renderer.lives.presences)
            elif said != self._told:
                now = {entry[0]: entry for entry in said}
                kept = {entry[0] for entry in self._told if now.get(entry[0]) == entry}
                self._likely = {n: a for n, a in self._likely.items() if n in kept}
            if self._overlay is None or said != self._told:
                self._overlay = self._head + panel_tail(frame, self._notes, self._likely)
                self._told = said
            overlay = self._overlay
        self.renderer.draw(self.screen, frame, overlay)
        if self.prompt.active:
            self.prompt.draw(self.screen, self.renderer)
            self.renderer.invalidate()
        if self.renderer.incremental:
            pygame.display.update(self.renderer.dirty)
        else:
            pygame.display.flip()
        if self.snapshots is not None and self.snapshots.due():
            self._snapshot(frame)

    def _refreshing(self, frame: Frame) -> Iterator[None]:
        """The overlay's next lines, step by step: each stage's percentiles, the notices, each
        changed line's text render; the lines take over when all is done."""
        lines: list[str] | None = None
        for lines in overlay_steps(frame, self.stats):
            if lines is None:
                yield
        assert lines is not None
        notes = self._notice_lines()
        for line in lines + notes:
            for cell in screens.cells(line):
                screens.panel_line(cell)   # the panel is composed from these when it is drawn
                yield
        self._head, self._notes = lines, notes

    def _events(self) -> None:
        for ev in pygame.event.get():
            if ev.type == pygame.KEYDOWN and (self.prompt.active or ev.key == pygame.K_F2):
                cmd = self.prompt.handle(ev)
                if cmd is not None and self.commands is not None:
                    self.commands.put(cmd)
                continue
            if ev.type == pygame.QUIT or (ev.type == pygame.KEYDOWN and ev.key == pygame.K_ESCAPE
                                          and (not self.kiosk or self.show_overlay)):
                if self.stop is not None:
                    self.stop.set()
            elif ev.type in (pygame.MOUSEBUTTONDOWN, pygame.MOUSEMOTION, pygame.MOUSEBUTTONUP):
                self._pointer(ev)
            elif ev.type == pygame.KEYDOWN:
                if ev.key == self.service_key or (not self.kiosk
                                                  and ev.key in (pygame.K_F1, pygame.K_o)):
                    self.show_overlay = not self.show_overlay
                elif ev.key in KEY_COMMANDS and self.commands is not None:
                    self.commands.put(KEY_COMMANDS[ev.key])

    def _pointer(self, ev: pygame.event.Event) -> None:
        """Mouse fingers for touch engines (see :mod:`tabletop.pointer`)."""
        from tabletop.pointer import POINTER
        if ev.type == pygame.MOUSEBUTTONUP:
            POINTER.release()
            return
        x, y = (float(v) for v in apply_homography(np.linalg.inv(self.renderer.map.H),
                                                    np.array([ev.pos], dtype=float))[0])
        if ev.type == pygame.MOUSEBUTTONDOWN and ev.button == 1:
            POINTER.press(x, y, pin=bool(pygame.key.get_mods() & pygame.KMOD_SHIFT))
        elif ev.type == pygame.MOUSEMOTION:
            POINTER.move(x, y)

    def _snapshot(self, frame: Frame) -> None:
        """The view as it is, with the overlay of this moment (sources' health) unless shown."""
        surface = self.screen
        if self.snapshot_overlay and not self.show_overlay:
            surface = self.screen.copy()
            # its lines (figures of this minute) are not kept: kept, a kiosk's snapshot a
            # minute filled the overlay's line cache to 257 renders (4.5 MB) over 15 minutes,
            # cleared and filled again, the heap growing as it filled (bench/gallery_soak.py)
            # the lines the shown overlay would have: a kiosk's refused config edit is
            # seen from afar (its notice was left out)
            lines = overlay_lines(frame, self.stats, self._notice_lines(),
                                  suspected(frame, self.renderer.lives.presences))
            self.renderer.draw_overlay(surface, lines, keep=False)
        self.snapshots.save(surface)

    def close(self) -> None:
        if self.snapshots is not None:
            self.snapshots.close()
        pygame.display.quit()


def scaled_homography(homography: np.ndarray | None, asked: tuple[int, int],
                      given: tuple[int, int]) -> np.ndarray | None:
    """``table_to_projector`` (pixels of ``asked``, the projector size it was fitted at) for a
    window of ``given`` pixels filling the same projector: a fullscreen window the display
    could not switch to ``view.size`` is its desktop's size, which the projector stretches over
    the same table. None (the uncalibrated fit, made for the window it gets) stays None."""
    if homography is None:
        return None
    sx, sy = given[0] / asked[0], given[1] / asked[1]
    return np.diag([sx, sy, 1.0]) @ np.asarray(homography, dtype=float)
