"""Runs the installation of ``tabletop run``: kiosk and studio parts wired onto the loop, and
configuration edits applied by rebuilding the installation (or refused, see
:mod:`tabletop.kiosk.watch`)."""

from __future__ import annotations

import copy
import ctypes
import gc
import logging
import threading
import time
from pathlib import Path
from typing import Any, Callable

from tabletop.app import Installation, build_live
from tabletop.frames import Frame, InputError
from tabletop.kiosk.attract import Attract, OneMoment, attract_performers
from tabletop.kiosk import last_good
from tabletop.kiosk.actions import ActionReloader
from tabletop.kiosk.health import (Heartbeat, HealthReporter, WatchdogPing,
                                   recording_status, snapshot_status)
from tabletop.kiosk.notify import Notifier
from tabletop.kiosk.paths import kiosk_log, kiosk_paths
from tabletop.plugins import scripted
from tabletop.registry import BuildContext
from tabletop.studio.reloader import BehaviorReloader, keep_playing
from tabletop.studio.session import end_drawing

log = logging.getLogger("tabletop")


def kiosk_view(cfg: dict[str, Any], kiosk: bool) -> dict[str, Any]:
    """The config as the kiosk runs it: fullscreen, no overlay until the service key."""
    if not kiosk:
        return cfg
    cfg = copy.copy(cfg)
    cfg["view"] = dict(cfg["view"], fullscreen=True, overlay=False)
    return cfg


class Runner:
    """Builds and runs the installation; rebuilds it when the watched config changes."""

    def __init__(self, config_path: Path, cfg: dict[str, Any], headless: bool = False,
                 record_path: Path | None = None, kiosk: bool = False,
                 studio: bool = False, clock: Callable[[], float] | None = None,
                 wrap_source: Callable[[Any, dict], Any] | None = None,
                 prepared: Any = None,
                 config_error: str | None = None, strict: bool = False) -> None:
        self.config_path = Path(config_path)
        self.base = self.config_path.resolve().parent
        self.cfg, self.headless, self.record_path = cfg, headless, record_path
        self.kiosk = kiosk or cfg["kiosk"]["enabled"]
        self.studio_asked = studio   # run --studio
        self._studio_of(cfg)
        self.clock, self.wrap_source = clock, wrap_source   # simulated time (tests, soaks)
        self.prepared = prepared    # a warm spare's engines (tabletop.kiosk.spare), built for cfg
        # the config file's refusal when cfg is the last good one (tabletop.kiosk.last_good)
        self.config_error = config_error
        # the first build refuses what only a first start should (app.build_recorder); the
        # rebuilds of config edits run on where they can
        self.strict = strict
        self.started = (clock or time.monotonic)()
        self.stop = threading.Event()
        self.pending: dict[str, Any] | None = None
        # the pending edit waits for a studio take (said); cleared with the pending edit
        self._waiting = False
        self._notes: list[str] = []    # said by the next studio (what an applied edit did)
        self.notifier = Notifier()
        self.watcher = None
        self.inst = None
        self.ticks = 0
        self.run_s = 0.0   # seconds the frame loops ran (builds and closing not counted)
        # why the recordings of installations that ran before stopped (each "FILE: why")
        self.recording_failures: list[str] = []
        self.studio: Any = None
        self.reporter: Any = None
        # engine name -> (behaviour, what it was trained from) the installation before played
        self._playing: dict[str, tuple] = {}
        if self.kiosk:
            kiosk_log(cfg, kiosk_paths(cfg, self.base)["log_file"])
            if config_error is not None:
                last_good.say(self.config_path, config_error)
            import faulthandler
            faulthandler.enable()     # a native crash leaves its Python stack in the crash log

    def _studio_of(self, cfg: dict[str, Any]) -> None:
        """Whether ``cfg`` runs the studio, and for every engine (``studio_all``, MOP included).
        Taken again at each build, so that an applied edit that turns the studio on (a
        designer engine, ``studio.enabled``) builds the studio at once, not at the next
        restart."""
        self.studio_all = self.studio_asked or cfg["studio"]["enabled"]
        # designer targets always go through the studio: Puppet Master engines in designer
        # mode, MOP characters and touch-pose characters (drawn once a designer key is pressed)
        self.studio_on = self.studio_all or any(
            (e.get("designer") or {}).get("enabled") or e["kind"] in ("mop", "touch_pose")
            for e in cfg["engines"])

    def _apply(self, cfg: dict[str, Any]) -> None:
        self.pending, self._waiting = cfg, False
        self._apply_when_idle()

    def _apply_when_idle(self, frame: Frame | None = None) -> None:
        """Stop the loop for the pending edit's rebuild, unless a studio take is under way
        (recorded, in parts or tried): a rebuild would drop it. The edit then waits, said once
        on the status line, until the take is kept or dropped."""
        if self.pending is None or self.inst is None:
            return
        studio = self.studio
        if studio is not None and studio.state != "idle":
            if not self._waiting:
                self._waiting = True
                studio.say("config edit: applied once this take is kept (K) or dropped (X)")
            return
        self._save_run_only(self.pending)
        # the frame loop pauses for the rebuild: a supervisor (or systemd) waits for the next
        # READY=1 as for a start, rather than killing the rebuild as a stall after stall_s
        self.notifier.send("RELOADING=1")
        self.inst.loop.stop.set()

    def _save_run_only(self, cfg: dict[str, Any]) -> None:
        """Before the rebuild: takes a MOP engine kept "for this run only" (it had no library)
        would be dropped by it. The keep's own line advises giving the engine a library in the
        config, so a designer who does so expects them kept: they are saved into the new
        config's library. An edit that gives none applies all the same (a kiosk edit must not
        wait on a take list), and says which takes it dropped, in the log and on the status
        line of the rebuilt studio."""
        if self.studio is None:
            return
        libs = {e["name"]: e.get("library") for e in cfg["engines"] if e["kind"] == "mop"}
        for t in self.studio.targets.values():
            names = list(getattr(t, "run_only", ()))
            if not names:
                continue
            lib = libs.get(t.stage.name)
            if lib is not None:
                for line in t.save_run_only(self.base / lib):
                    log.info("config edit: %s", line)
                    self._notes.append(line)
                continue
            note = (f"config edit dropped {t.name}'s takes kept for this run only: "
                    f"{', '.join(names)} (engine {t.stage.name!r} has no library)")
            log.warning("%s", note)
            self._notes.append(note)
            t.run_only = []

    def _build(self, cfg: dict[str, Any]) -> Installation:
        """The installation of ``cfg`` with the studio, kiosk and health parts on its loop."""
        prepared, self.prepared = self.prepared, None
        self._studio_of(cfg)
        ready = None if prepared is None or prepared.cfg is not cfg else (
            prepared.context, prepared.engines)
        inst = build_live(kiosk_view(cfg, self.kiosk), headless=self.headless,
                          record_path=self.record_path, clock=self.clock,
                          wrap_source=self.wrap_source, prepared=ready,
                          header_extra={"studio": {"all": self.studio_all}}
                          if self.studio_on else None, strict=self.strict,
                          # a kiosk's start, fall-back or edit runs on without a behaviour
                          # whose files went bad: an edit of another part applies (refused, its
                          # fall-back rebuild dropped that behaviour all the same)
                          kiosk_start=self.kiosk,
                          # (behaviours the studio holds are not kept: said to start without)
                          keeping=() if self.studio_on else self._playing)
        self.strict = False
        loop = inst.loop
        # (``record_path``, run --record, stays: each installation records to the next free name
        # of it, FILE-2.jsonl..., as a supervised restart does, so an applied config edit never
        # ends the recording for the rest of the run.)
        # providers of status fields; a part that is off still gives the fields the status
        # promises (README, health.py): without them a kiosk without a studio, or with
        # watch_config false, sent no "studio" (or "config", "config_error") at all
        extra: list = []
        self._notes, notes = [], self._notes
        # an edit waiting for a studio take, shown as long as it waits (not only said once)
        extra.append(lambda: {"config_pending": self._waiting})
        if self.watcher is None:      # (the watcher gives them otherwise)
            extra.append(lambda: {"config": str(self.config_path),
                                  "config_error": self.config_error})
        if not self.studio_on:
            extra.append(lambda: {"studio": None})
        held: dict = {}
        self.studio = None
        if self.studio_on:
            # (imported here: the studio's modules, the MOP and touch-pose take machinery, were
            # 0.026-0.039 CPU s of every other run's start)
            from tabletop.studio.build import attach_studio
            self.studio = attach_studio(inst, cfg, self.base, all_engines=self.studio_all)
            if notes:
                self.studio.say("; ".join(notes))
            loop.hooks.append(self._apply_when_idle)   # an edit waiting for a take
            extra.append(self.studio.status)
            held = {t.engine: t for t in self.studio.targets.values() if hasattr(t, "engine")}
        # outside the studio too; a behaviour an applied edit's new files refused plays on
        playing, self._playing = self._playing, {}
        # (one the studio drives keeps it too; its target reloads the folder)
        reloaders = [BehaviorReloader(e, kept=keep_playing(e, playing.get(e.name)),
                                      target=held.get(e))
                     for e in loop.engines if getattr(e, "folder", None) is not None]
        for r in reloaders:
            loop.filters.insert(0, r)    # (recorded for replays)
        for e in loop.engines:   # MOP actions followed on disk: fixed, replaced or gone bad
            if getattr(e, "missing", None) or self.kiosk and getattr(e, "watched", None):
                loop.filters.insert(0, ActionReloader(e))
        # a behaviour file that went bad on disk (the character plays the version read before,
        # or none at a start), as the log and the character's label say
        # , and each action a character goes without (a MOP clip or template, a touch-pose
        # action file, unreadable)
        extra.append(lambda: {"behavior_errors": [f"{r.engine.name}: {r.problem}"
                                                  for r in reloaders if r.problem] + [
            f"{e.name}: {why}" for e in loop.engines for why in getattr(e, "start_problems", ())]})
        if self.kiosk:
            extra.append(self._attract(inst, cfg))
            self._kiosk_view(inst, cfg["kiosk"])
        loop.filters.append(OneMoment(cfg["kiosk"]["grace_s"], clock=loop.clock))
        view = next((s for s in loop.sinks if s.name == "view"), None)
        if self.watcher is not None:
            loop.hooks.append(self.watcher)
            extra.append(self.watcher.status)
            w = self.watcher
            if view is not None:
                view.notices.append(lambda: [f"config refused: {w.error}"] if w.error else [])
        if self.kiosk:
            extra.append(recording_status(inst.recorder))
            extra.append(snapshot_status(view))
            self._health(inst, cfg, extra)
        if view is not None:
            view.notices.append(lambda: ["config edit waits: K keeps the take, X drops it"]
                                if self._waiting else [])
        loop.hooks.append(WatchdogPing(self.notifier, clock=loop.clock))
        return inst

    def _drop(self) -> None:
        """Free the installation that ran (its loop closed it) before the next one is built,
        so that the build reuses its memory (both alive during the build, a kiosk of the
        gallery soak's config grew 6.5 MB an applied edit; freed first, with :func:`trim_heap`
        and the studio's one drawing thread, 0.44 MB an edit over 20 edits, file descriptors
        flat).
        A recording of it that failed is remembered for ``tabletop run``'s exit status, and
        each Puppet Master behaviour it played from its folder (:attr:`_playing`), which the
        next build keeps playing where its folder now holds a bad file."""
        recorder = self.inst.recorder if self.inst is not None else None
        if recorder is not None and recorder.incomplete:
            self.recording_failures.append(recorder.incomplete)
        self._playing = {e.name: played for e in (self.inst.engines if self.inst else ())
                         if (played := getattr(e, "played_from", None)) is not None
                         and played[0] is e.behavior}
        self.inst = self.studio = self.reporter = None
        gc.collect()

    def _attract(self, inst: Installation,
                 cfg: dict[str, Any]) -> Callable[[], dict[str, float]]:
        """Attract mode on the loop; returns its status provider (``idle_s``)."""
        loop, k = inst.loop, cfg["kiosk"]
        ctx = BuildContext(inst.context.table, inst.context.rate_hz, cfg, self.base)
        options = dict(k["attract"], name="attract")
        if not options["performers"]:
            options["performers"] = attract_performers(cfg, inst.context.table)
        script = scripted.build(options, ctx)
        attract = Attract(script.poses, k["idle_s"], k["handover_s"], clock=loop.clock)
        loop.filters.append(attract)
        return lambda: {"idle_s": round(attract.idle_for(loop.clock()), 1)}

    def _health(self, inst: Installation, cfg: dict[str, Any], extra: list) -> None:
        """Status file and heartbeat on the loop, closed with the sinks."""
        loop, k = inst.loop, cfg["kiosk"]
        hb = k["heartbeat"]
        self.reporter = HealthReporter(
            k["name"], loop.stats, hb["every_s"], kiosk_paths(cfg, self.base)["status_file"],
            Heartbeat(hb["host"], hb["port"]) if hb["enabled"] else None,
            extra=lambda: {key: v for fn in extra for key, v in fn().items()},
            clock=loop.clock, started=self.started)
        loop.hooks.append(self.reporter)
        loop.sinks.append(_Closer("health", self.reporter.close))

    @staticmethod
    def _kiosk_view(inst: Installation, k: dict[str, Any]) -> None:
        from tabletop.kiosk.settings import service_key_code
        key = service_key_code(k["service_key"])   # (a name it has not is refused at load)
        for s in inst.sinks:
            if s.name == "view":
                s.kiosk, s.service_key = True, key

    def _load(self, path: Path) -> Any:
        """The edited config at ``path``, refused (InputError) as ``run --kiosk`` refuses a
        config at its start: under ``--kiosk`` a config whose ``kiosk.enabled`` is off is
        validated without the heartbeat check (not sent to its own osc source), so it runs
        here too. (The other start check, kiosk files distinct, depends on files an edit
        that names none cannot change: the config's own name and the defaults.)"""
        from tabletop.config import load_config
        try:
            cfg = load_config(path)
        except InputError as exc:
            # the running config, which a kiosk started without the actions whose files it
            # cannot read (tabletop.kiosk.last_good.load), is no edit to refuse; any other is
            cfg = load_config(path, start_without=True)
            if not self.kiosk or cfg != self.cfg:
                # refused for a file it names: the watcher validates it again once that changes
                exc.files = tuple(ref.resolved for ref in cfg.refs if ref.embed)  # type: ignore
                raise
        if self.kiosk:
            from tabletop.config_ports import check_heartbeat
            check_heartbeat(cfg)
        return cfg

    def run(self, seconds: float | None = None) -> int:
        from tabletop.kiosk.watch import ConfigWatcher
        if self.kiosk and self.cfg["kiosk"]["watch_config"] or self.studio_on:
            # the file as the running configuration was read from it (not the last good one
            # a refused file left running: that look is to say the refusal)
            read = (getattr(self.cfg, "read", None) if self.config_error is None
                    and Path(getattr(self.cfg, "file", "")) == self.config_path else None)
            # (validated off the frame loop: examples/mop.yaml's 20-33 ms of CPU in one tick)
            self.watcher = ConfigWatcher(self.config_path, self.cfg, self._load, self._apply,
                                         read=read, background=True)
            self.watcher.error = self.config_error
        try:
            self._run_loops(seconds)
        finally:   # the studio's drawing thread served every build; it ends with the run
            end_drawing()
            if self.watcher is not None:
                self.watcher.close()
        if self.reporter is not None:      # its loop closed it: the file says it stopped
            self.reporter.stopped()
        self.notifier.send("STOPPING=1")
        return 0

    def _run_loops(self, seconds: float | None) -> None:
        """Build and run the installation, rebuilt at each applied config edit, until stopped
        or ``seconds`` of run time have passed."""
        cfg = self.cfg
        left = seconds              # run time, not counting the builds
        rebuilt = False
        while True:
            if rebuilt:
                self._drop()
            try:
                self.inst = self._build(cfg)
            except InputError as exc:
                if cfg is self.cfg:
                    raise
                log.error("the new configuration cannot start (%s); back to the previous one", exc)
                cfg = self.cfg
                if self.watcher is not None:
                    self.watcher.current, self.watcher.error = cfg, str(exc)
                continue
            self.cfg = cfg
            if rebuilt:
                # The build's own garbage collected (the previous installation's by _drop)
                # before the new loop freezes what exists out of the collector's passes
                # (Loop.run): frozen, an old installation was never freed, +66 and +72 MB
                # resident and +6 threads at the two edits of a gallery soak.
                gc.collect()
                trim_heap()
            rebuilt = True
            if self.kiosk and getattr(cfg, "raw", None) is not None:
                last_good.remember(self.config_path, cfg)   # it built: the next start's fallback
            ran = threading.Event()     # this loop's run is over: its relay ends
            relay = threading.Thread(target=_relay, args=(self.stop, self.inst.loop.stop, ran),
                                     name="stop-relay", daemon=True)
            relay.start()
            t0 = time.monotonic()
            try:
                self.ticks += self.inst.loop.run(seconds=left)
            finally:
                ran.set()
                relay.join()
            self.run_s += self.inst.loop.ran_s
            if left is not None:
                left -= time.monotonic() - t0
            if self.pending is None or self.stop.is_set() or (left is not None and left <= 0):
                break
            cfg, self.pending, self._waiting = self.pending, None, False


def trim_heap() -> None:
    """Give the C heap's free pages back to the system (glibc's ``malloc_trim``; nothing where
    the C library has none). A rebuilt installation frees the previous one's memory into the
    heap, where it stayed resident: the memory in use grew about 0.4 MB an applied config edit,
    the resident memory 6.5 MB (see :meth:`Runner._drop` for the figures)."""
    try:
        trim = ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError, TypeError):   # TypeError: no C library by that name
        return
    trim(0)


def _relay(outer: threading.Event, inner: threading.Event, ran: threading.Event) -> None:
    """Sets ``inner`` when ``outer`` is set (the signal handler's stop ends the current loop);
    returns once either is set or the loop's run is over (``ran``), within 0.2 s."""
    while not inner.is_set() and not ran.is_set():
        if outer.wait(0.2):
            inner.set()
            return


class _Closer:
    """A sink that only closes something when the loop closes its sinks."""

    def __init__(self, name: str, close: Callable[[], None]) -> None:
        self.name, self._close = name, close

    def consume(self, frame: Frame) -> None:
        pass

    def close(self) -> None:
        self._close()
