"""Wiring: builds the installation from a validated config and runs it until told to stop.

Build order: the installation's calibration, puck tracker (shared with the camera sources for
region-of-interest predictions), sources, engines (in config order), sinks (the recorder is
built first so a folder it cannot use fails before a window opens; frames go to the view and
configured sinks, then the recorder). Ctrl-C, SIGTERM and SIGHUP end the run cleanly: sources
closed, the recording flushed and complete.
"""

from __future__ import annotations

import logging
import signal
import threading
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Collection, Iterator

from tabletop import registry
from tabletop.cli import catch_stop_signals
from tabletop.frames import Engine, InputError, Sink
from tabletop.live_inputs import Tracker
from tabletop.loop import CommandQueue, FrameInputs, LatestMeasurements, LiveInputs, Loop, LoopStats
from tabletop.registry import BuildContext

if TYPE_CHECKING:
    import numpy as np

    from tabletop.recorder import Recorder

log = logging.getLogger("tabletop")


@dataclass
class Installation:
    """Everything a run needs, built and ready: ``loop.run()`` starts it."""

    loop: Loop
    context: BuildContext
    engines: list[Engine] = field(default_factory=list)
    sinks: list[Sink] = field(default_factory=list)

    @property
    def recorder(self) -> Recorder | None:
        """The recorder sink, if this installation records."""
        from tabletop.recorder import Recorder
        return next((s for s in self.sinks if isinstance(s, Recorder)), None)


def configure_logging(verbose: bool = False) -> None:
    """INFO and above; ``verbose``: the project's own debug messages too (its loggers are
    "tabletop" and below; the libraries' stay at INFO: matplotlib's font search alone put
    146 "tabletop: DEBUG: findfont: ..." lines before a studio's first take)."""
    logging.basicConfig(level=logging.INFO, format="tabletop: %(levelname)s: %(message)s")
    if verbose:
        logging.getLogger("tabletop").setLevel(logging.DEBUG)


def _context(cfg: dict[str, Any], calibration: dict[str, Any] | None = None) -> BuildContext:
    """The build context; the installation's calibration (the top-level file, or a replayed
    recording's) is shared first, so the view maps the table with it."""
    table = (cfg["table"]["width"], cfg["table"]["height"])
    base = Path(getattr(cfg, "base", None) or cfg.get("_base", "."))
    ctx = BuildContext(table=table, rate_hz=cfg["loop"]["rate_hz"], config=cfg, base=base)
    from calibration.files import calibration_from_dict, load_calibration
    loaded = None
    if calibration is not None:
        loaded = calibration_from_dict(calibration, "the recording's calibration")
    elif cfg.get("calibration") is not None:
        loaded = load_calibration(cfg["calibration"])
    if loaded is not None:
        ctx.shared.update(calibration=loaded, calibration_dict=loaded.to_dict())
        if loaded.table_to_projector is not None:
            ctx.shared["table_to_projector"] = loaded.table_to_projector
    return ctx


def build_tracker(cfg: dict[str, Any], ctx: BuildContext) -> Tracker:
    """The configured puck tracker, or the pass-through one when no tracking plugin is installed."""
    tracking = registry.optional_module("tabletop.plugins.tracking")
    if tracking is None:
        return LatestMeasurements()
    controls = ((cfg.get("studio") or {}).get("markers") or {}).values()
    return tracking.build_tracker(cfg["tracking"], ctx, [m for m in controls if m is not None])


def build_engines(cfg: dict[str, Any], ctx: BuildContext) -> list[Engine]:
    return [registry.plugin_module("engine", e["kind"]).build(e, ctx) for e in cfg["engines"]]


HEADER_PARTS = 4
"""A recording part's size, in headers, where ``recorder.max_mb`` is below one header."""


def build_recorder(cfg: dict[str, Any], ctx: BuildContext, record_path: Path | None,
                   header: dict[str, Any] | None = None, strict: bool = False,
                   refuse_full: bool = False) -> Sink | None:
    """The recorder: to ``record_path`` when given, else as the ``recorder`` section says.
    A folder that cannot be written fails at start-up naming its key when ``strict``; otherwise
    the installation starts without recording and tries again (see the Recorder). A ``max_mb``
    that this config's header alone reaches would start a part every frame (every part repeats
    the header: the config and the files it names, 0.15 MB with one shipped behaviour; 480 files in
    8 s, ``keep`` removing them as fast): ``strict`` (a start outside a kiosk, where someone reads
    the error) refuses it; otherwise (a kiosk's start, which may be a restart by its supervisor or
    by systemd; a config edit; after a named file grew) one warning is logged and parts of
    :data:`HEADER_PARTS` headers are recorded, so a running table never goes down over it.
    ``refuse_full``: a full disk at the start is refused too (see the Recorder)."""
    from tabletop.parts import header_line
    from tabletop.recorder import MB, Recorder, session_header
    from tabletop.recordings import new_session
    from tabletop.schema import ConfigError
    rec = cfg["recorder"]
    if record_path is None and not rec["enabled"]:
        return None
    if header is None:
        header = session_header(cfg, ctx.shared.get("calibration_dict"))
    size = len(header_line(header, order=1, part=1, session=new_session()))
    max_mb = rec["max_mb"]
    if max_mb is not None and size >= max_mb * MB:
        why = (f"{getattr(cfg, 'file', 'config')}: recorder.max_mb: {max_mb:g} MB is less than "
               f"the header every part of the recording begins with ({size / MB:.2f} MB: the "
               f"config and the files it names)")
        if strict:
            raise ConfigError(f"{why}; give several times that")
        max_mb = HEADER_PARTS * size / MB
        log.warning("%s; recording parts of %.2f MB instead", why, max_mb)
    where = dict(path=record_path) if record_path is not None else (
        dict(path=rec["path"]) if rec["path"] is not None else dict(folder=rec["folder"]))
    try:
        return Recorder(header=header, max_mb=max_mb, keep=rec["keep"], strict=strict,
                        refuse_full=refuse_full, **where)
    except InputError as exc:
        if record_path is not None:
            raise
        key = "recorder.path" if rec["path"] is not None else "recorder.folder"
        raise ConfigError(f"{getattr(cfg, 'file', 'config')}: {key}: {exc}") from None


def projector_homography(cfg: dict[str, Any], ctx: BuildContext) -> np.ndarray | None:
    """The calibration's ``table_to_projector`` (a camera source's, else the config's), or
    None: the view then fits the table into the window. A view size other than the projector
    size the calibration was fitted at is refused (CalibrationError, one line)."""
    cal = ctx.shared.get("calibration")
    if ctx.shared.get("table_to_projector") is None:
        if cfg.get("calibration") is None:
            return None
        from calibration.files import load_calibration
        cal = load_calibration(cfg["calibration"], require_table=False)
    cal.check_projector_size(tuple(cfg["view"]["size"]))
    return cal.table_to_projector


def build_sinks(cfg: dict[str, Any], ctx: BuildContext, headless: bool,
                record_path: Path | None, stats: LoopStats, commands: CommandQueue,
                stop: threading.Event, view: bool = True,
                header: dict[str, Any] | None = None, strict: bool = False,
                refuse_full: bool = False) -> list[Sink]:
    # The recorder first: a folder it cannot use fails before a window opens.
    recorder = build_recorder(cfg, ctx, record_path, header, strict, refuse_full)
    sinks: list[Sink] = []
    try:
        if view and cfg["view"]["enabled"]:
            from tabletop.schema import ConfigError
            try:
                homography = projector_homography(cfg, ctx)
                # the display started (a display named but not there refused) before the
                # drawing's modules load their compiled kernels: such a refused start (a
                # kiosk's, restarted until its X server is back) 1.14 -> 0.6 CPU s
                from tabletop.display import start_view_display
                start_view_display(headless or cfg["view"]["headless"])
                from tabletop.drawing.characters import configured_parts
                from tabletop.view import ProjectorView, invitation
                sinks.append(ProjectorView(ctx.table, cfg["view"], stats=stats,
                                           commands=commands, stop=stop, headless=headless,
                                           homography=homography,
                                           invitation=invitation(cfg["engines"]),
                                           parts=configured_parts(cfg["engines"])))
                if cfg["view"]["calibration_check"]:
                    from tabletop.live_check import live_check
                    sinks.append(live_check(cfg, sinks[-1], ctx.shared.get("sources", ())))
            except ConfigError as exc:  # e.g. view.display: a display the machine has not
                raise ConfigError(f"{getattr(cfg, 'file', 'config')}: {exc}") from None
        for s in cfg["sinks"]:
            sinks.append(registry.plugin_module("sink", s["kind"]).build(s, ctx))
    except BaseException:
        if recorder is not None:
            recorder.discard()
        raise
    if recorder is not None:
        sinks.append(recorder)
    return sinks


def build_live(cfg: dict[str, Any], headless: bool = False, record_path: Path | None = None,
               stats: LoopStats | None = None, stop: threading.Event | None = None,
               clock: Callable[[], float] | None = None,
               wrap_source: Callable[[Any, dict], Any] | None = None,
               header_extra: dict[str, Any] | None = None,
               prepared: tuple[BuildContext, list[Engine]] | None = None,
               strict: bool = True, kiosk_start: bool = False,
               keeping: Collection[str] = ()) -> Installation:
    """A live installation from a validated config: sources, tracker, engines, view, recorder.

    ``stop`` (e.g. set by a signal while it is built) ends its run. ``clock`` (seconds)
    replaces the monotonic clock and unpaces the loop (simulated time:
    :mod:`tabletop.kiosk.simulate`); ``wrap_source(source, entry)`` may wrap each source.
    ``header_extra``: more keys for a recording's header (the studio's). ``prepared``: the
    context and engines already built for ``cfg`` (a kiosk's warm spare). ``strict`` (the
    default, as the Recorder's own): refuse a recorder ``max_mb`` below the header or a
    recording folder that cannot be written (a start outside a kiosk, where someone reads the
    error; see :func:`build_recorder`); a kiosk's start, which may be a restart, passes False
    and runs on.
    ``kiosk_start``: a behaviour folder holding a bad file starts its character without it
    (:func:`tabletop.plugins.puppet_master.build`) instead of refusing the installation;
    ``keeping``: the names of characters whose behaviour read before plays on in that case
    (:func:`tabletop.studio.reloader.keep_playing` says so), not said to start without it."""
    from tabletop.config_checks import unmoved_engine_pucks
    for said in unmoved_engine_pucks(cfg):
        log.warning("%s", said)
    ctx = _context(cfg) if prepared is None else prepared[0]
    ctx.shared["kiosk_start"] = kiosk_start
    ctx.shared["keeping"] = frozenset(keeping)
    stats, commands, stop = stats or LoopStats(), CommandQueue(), stop or threading.Event()
    ctx.shared.update(stats=stats, commands=commands, stop=stop)
    if clock is not None:
        ctx.shared["clock"] = clock
    tracker = build_tracker(cfg, ctx)
    ctx.shared["tracker"] = tracker
    sources = [registry.plugin_module("source", s["kind"]).build(s, ctx) for s in cfg["sources"]]
    if wrap_source is not None:
        sources = [wrap_source(src, entry) for src, entry in zip(sources, cfg["sources"])]
    ctx.shared["sources"] = sources
    engines = build_engines(cfg, ctx) if prepared is None else prepared[1]
    # characters a kiosk started without their bad behaviour: a replay starts them so too
    without = {e.name: e.problem for e in engines if getattr(e, "problem", "")}
    if without:
        header_extra = {**(header_extra or {}), "started_without": without}
    header = None
    if header_extra:
        from tabletop.recorder import session_header
        header = session_header(cfg, ctx.shared.get("calibration_dict"), **header_extra)
    sinks = build_sinks(cfg, ctx, headless, record_path, stats, commands, stop, header=header,
                        strict=strict)
    for s in sinks:        # (the recorder: a later part carries its engines' states)
        if hasattr(s, "state_of"):
            from tabletop.parts import part_states
            s.state_of = lambda: part_states(engines)
    timing = {} if clock is None else {"clock": clock, "paced": False}
    loop = Loop(LiveInputs(sources, tracker), engines, sinks, rate_hz=cfg["loop"]["rate_hz"],
                stats=stats, commands=commands, stop=stop, **timing)
    loop.realtime_priority = cfg["loop"].get("realtime_priority", 0)
    if any(getattr(e, "mouse", False) for e in engines):
        from tabletop.pointer import with_mouse_fingers
        loop.filters.insert(0, with_mouse_fingers)   # recorded, so a replay has them
    return Installation(loop, ctx, engines, sinks)


def build_replay(cfg: dict[str, Any], frames: Iterator, fast: bool, headless: bool = False,
                 record_path: Path | None = None, view: bool = True,
                 header: dict[str, Any] | None = None) -> Installation:
    """Recorded frames fed through the engines and sinks of the recorded config; ``header``
    (the recording's) gives the calibration and heads a new recording made with ``record_path``."""
    ctx = _context(cfg, (header or {}).get("calibration"))
    without = (header or {}).get("started_without")
    ctx.shared["started_without"] = dict(without) if isinstance(without, dict) else {}
    stats, commands, stop = LoopStats(), CommandQueue(), threading.Event()
    ctx.shared.update(stats=stats, commands=commands, stop=stop)
    # A replay records only to --out, in one file (the comparison of a whole session).
    cfg = dict(cfg, recorder=dict(cfg["recorder"], enabled=False, max_mb=None, keep=None))
    engines = build_engines(cfg, ctx)   # (a MOP engine checks its started_without itself)
    out_header = None if header is None else {
        k: v for k, v in header.items() if k not in ("created", "part")}
    # (an --out that cannot be started, a full disk too, is refused before anything plays:
    # a replay is read by someone, never a table to keep running)
    sinks = build_sinks(cfg, ctx, headless, record_path, stats, commands, stop, view=view,
                        header=out_header, strict=True, refuse_full=True)
    loop = Loop(FrameInputs(frames, honour_times=not fast, stop=stop), engines, sinks,
                rate_hz=cfg["loop"]["rate_hz"], stats=stats, commands=commands, stop=stop,
                paced=False)
    return Installation(loop, ctx, engines, sinks)


@contextmanager
def stop_on_signals(stop: threading.Event) -> Iterator[list[str]]:
    """Within the block, SIGINT, SIGTERM and SIGHUP (a closed terminal or session; not under
    ``nohup``, see :func:`tabletop.cli.catch_stop_signals`) set ``stop`` instead of killing
    the process, so the run ends cleanly; the block is given the list of the names of the
    signals received."""
    received: list[str] = []

    def handler(signum: int, _frame: Any) -> None:
        name = signal.Signals(signum).name
        log.info("%s received: stopping", name)
        received.append(name)
        stop.set()

    with catch_stop_signals(handler):
        yield received
