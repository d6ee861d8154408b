"""Wiring the studio onto a built installation: its targets, control markers, session log."""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from behaviors.worker import FINISH_S
from tabletop import library
from tabletop.frames import Frame
from tabletop.studio.folders import named_folder
from tabletop.studio.machine import Studio
from tabletop.studio.session import SessionLog, left_at_quit
from tabletop.studio.mop_target import MopTarget
from tabletop.studio.pose_target import TouchPoseTarget
from tabletop.studio.reloader import LibraryReloads, RecordedLibraries
from tabletop.studio.take import Target
from tabletop.studio.targets import PuppetMasterTarget

log = logging.getLogger("tabletop")

if TYPE_CHECKING:
    from tabletop.app import Installation
    from tabletop.frames import Engine


class Markers:
    """Control markers: a marker put on the table (seen for ``debounce_s``) sends its command
    once; lifting the record marker (gone for ``debounce_s``) while recording stops the take.
    ``next`` goes to the loop's command queue (the focus moves on the next tick)."""

    def __init__(self, ids: Mapping[str, int | None], studio: Studio, queue: Any = None,
                 debounce_s: float = 0.3) -> None:
        self.ids = {cmd: int(i) for cmd, i in ids.items() if i is not None}
        self.studio, self.queue, self.debounce_s = studio, queue, debounce_s
        self._on = {cmd: False for cmd in self.ids}
        self._since = {cmd: -math.inf for cmd in self.ids}

    def __call__(self, frame: Frame) -> Frame:
        present = {p.id for p in frame.pucks if p.state == "seen"}
        for cmd, mid in self.ids.items():
            on = mid in present
            if on == self._on[cmd]:
                self._since[cmd] = -math.inf
                continue
            if self._since[cmd] == -math.inf:
                self._since[cmd] = frame.t
            if frame.t - self._since[cmd] < self.debounce_s:
                continue
            self._on[cmd], self._since[cmd] = on, -math.inf
            if on and cmd == "next":
                if self.queue is not None:
                    self.queue.put("designer.next")
            elif on:
                self.studio.command(f"designer.{cmd}")
            elif cmd == "record" and self.studio.state in ("countdown", "recording"):
                self.studio.command("designer.stop")
        # marker pucks are controls, not characters' inputs
        markers = set(self.ids.values())
        if any(p.id in markers for p in frame.pucks):
            frame = dataclasses.replace(frame, pucks=tuple(
                p for p in frame.pucks if p.id not in markers))
        return frame


class StudioStage:
    """The studio as one frame filter: control markers, then the machine. What they take out of
    the frame (marker pucks, the designer commands) is kept in ``Frame.consumed["studio"]`` (the
    pucks taken and every command the stage was given), so a recording holds the studio's
    inputs and a replay runs the studio again on them (:func:`studio_input`)."""

    def __init__(self, markers: Markers, studio: Studio) -> None:
        self.markers, self.studio = markers, studio

    def close(self) -> None:
        """The loop closes: the take under way dropped (one tried logged), then, even when
        that fails, every target's worker ended, so none outlives the run, and the session's
        sheet being drawn waited for (the drawing thread serves the next build and ends with
        the run). All the waits share one :data:`~behaviors.worker.FINISH_S`: a kiosk's
        supervisor kills an installation that takes 10 s to stop."""
        deadline = time.monotonic() + FINISH_S
        try:
            self.studio.close()
        finally:
            for target in self.studio.targets.values():
                close = getattr(target, "close", None)
                if close is not None:
                    close(deadline)
            session = getattr(self.studio, "session", None)
            if session is not None:
                session.close(max(0.0, deadline - time.monotonic()))

    def __call__(self, frame: Frame) -> Frame:
        out = self.studio(self.markers(frame))
        if len(out.pucks) != len(frame.pucks) or out.commands != frame.commands:
            kept = {id(p) for p in out.pucks}
            taken = tuple(p for p in frame.pucks if id(p) not in kept)
            out = dataclasses.replace(out, consumed={
                **out.consumed, "studio": {"pucks": taken, "commands": frame.commands}})
        return out


def studio_input(frame: Frame) -> Frame:
    """A recorded frame as the studio stage was given it live: the pucks it took put back and
    its commands (the inverse of :class:`StudioStage` for replays)."""
    taken = frame.consumed.get("studio")
    if not taken:
        return frame
    return dataclasses.replace(frame, pucks=frame.pucks + tuple(taken.get("pucks", ())),
                               commands=tuple(taken.get("commands", frame.commands)),
                               consumed={k: v for k, v in frame.consumed.items() if k != "studio"})


def studio_targets(engines: Sequence[Engine], cfg: dict[str, Any], base: Path,
                   all_engines: bool) -> list[Target]:
    """A target for every Puppet Master engine in designer mode (every one with
    ``all_engines``: studio mode), for every character of every MOP engine and for every
    touch-pose engine."""
    from tabletop.plugins import puppet_master as pm
    from tabletop.schema import Context
    targets: list = []
    options = {e["name"]: e for e in cfg["engines"]}
    for e in engines:
        if isinstance(e, pm.PuppetMasterEngine):
            if e.designer is None:
                if not all_engines:
                    continue
                d = pm.DESIGNER.validate({"enabled": True}, "designer", Context("studio", base))
                lib = Path(d["library"])
                d["library"] = lib if lib.is_absolute() else base / lib
                d["main_puck"] = pm.designer_main_puck(e.main)
                if d["react_puck"] == d["main_puck"]:   # a main on puck 2: react with puck 1
                    d["react_puck"] = 1
                # its takes are kept under its name, or "behaviour" where no folder may have
                # it ("mein Liebling": K refused every take)
                d["name"] = e.name if library.NAME_RE.match(e.name) else "behaviour"
                e.designer = d
            targets.append(PuppetMasterTarget(e))
        elif hasattr(e, "core") and hasattr(e, "designed"):      # a touch-pose character
            targets.append(TouchPoseTarget(e))
        elif hasattr(e, "begin_take"):
            lib = options.get(e.name, {}).get("library")
            targets += [MopTarget(e, c, Path(lib) if lib else None) for c in e.order]
    named = {Path(e["behavior"]).resolve(): f"engines[{i}].behavior"
             for i, e in enumerate(cfg["engines"]) if e.get("behavior")}
    for t in targets:         # the keep's line names library folders relative to the config's
        t.base = base
        if isinstance(t, PuppetMasterTarget):
            t.config_named = named
    return targets


#: What a take saved at quit was, by the studio's state then (a session log's ``take_state``).
LEFT_AS = {"trying": "take tried, not kept,", "training": "take still training",
           "recording": "take still recorded",
           "ready": "sequential take's main part (its reaction not recorded)"}


def left_words(take: Path, state: str, reaction: Path | None, base: Path) -> str:
    """The next start's line on the take the last session saved at quit
    (:func:`~tabletop.studio.session.left_at_quit`'s): what it was and where it is."""
    where = named_folder(take.parent, base)
    if reaction is not None:
        return (f"studio: the last session's sequential take, its reaction cut short at quit, "
                f"is in {where}{take.name} (the main part) and {reaction.name} (the reaction so "
                "far), not in the library")
    return (f"studio: the last session's {LEFT_AS.get(state, 'take saved')} at quit is in "
            f"{where}{take.name} (not in the library)")


def attach_studio(inst: Installation, cfg: dict[str, Any], base: Path, all_engines: bool = True,
                  replay: bool = False) -> Studio:
    """Put the studio on ``inst``'s loop: the machine and markers as one filter
    (:class:`StudioStage`), library polling as a hook, the session log in ``studio.folder``
    (a ``replay`` draws no review sheets)."""
    s = cfg["studio"]
    targets = studio_targets(inst.loop.engines, cfg, base, all_engines)
    folder = Path(s["folder"] or base / "studio")
    left = None if replay else left_at_quit(folder)      # (before this session's log)
    session = SessionLog(folder, review=s["review"] and not replay)
    studio = Studio(targets, s["countdown_s"], log_try=session.log_try,
                    quiet=not all_engines)
    studio.session = session
    # a replay's studio folder is a temporary one: the take was saved by the run it replays
    studio.save_take = None if replay else session.save_take
    if left is not None:     # the designer's work the last session left: where it is
        said = left_words(*left, base)
        log.info("%s", said)
        for sink in inst.loop.sinks:     # on the operator overlay until the next take
            if hasattr(sink, "notices"):  # (not the studio's line: a replay makes that again)
                sink.notices.append(lambda: [said] if studio.state == "idle" and not
                                    studio.tries else [])
    ids = dict(s["markers"])
    for t in targets:       # an engine's own record marker (designer.record_marker)
        if getattr(t, "record_marker", None) is not None:
            ids["record"] = t.record_marker
    loop = inst.loop
    loop.filters.append(StudioStage(Markers(ids, studio, loop.commands, s["debounce_s"]), studio))
    loop.focus.extra.append(studio)
    for sink in loop.sinks:     # F2 refused at once when there is nothing to rename
        if hasattr(sink, "prompt"):
            sink.prompt.ask = studio.may_rename
    if replay:    # the library files the live run reloaded, written and reloaded as live
        loop.filters.insert(0, RecordedLibraries(studio, base))
        loop.hooks.append(lambda frame: studio.poll())
    else:         # reloaded between frames, the files read recorded in the next frame
        reloads = LibraryReloads(studio)
        loop.filters.insert(0, reloads)
        loop.hooks.append(reloads.poll)
    return studio
