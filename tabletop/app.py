"""Wiring: builds the installation from a validated config and runs it until told to stop.

Build order: puck tracker (shared with the camera sources for region-of-interest predictions),
sources, engines (in config order), sinks (view, recorder, configured sinks). Ctrl-C and SIGTERM
end the run cleanly: sources closed, the recording flushed and complete.
"""

from __future__ import annotations

import datetime as _dt
import logging
import signal
import threading
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator

from tabletop import registry
from tabletop.frames import Engine, Sink
from tabletop.loop import CommandQueue, FrameInputs, LatestMeasurements, LiveInputs, Loop, LoopStats
from tabletop.registry import BuildContext

log = logging.getLogger("tabletop")


@dataclass
class Installation:
    """Everything a run needs, built and ready: ``loop.run()`` starts it."""

    loop: Loop
    context: BuildContext
    engines: list[Engine] = field(default_factory=list)
    sinks: list[Sink] = field(default_factory=list)


def configure_logging(verbose: bool = False) -> None:
    logging.basicConfig(level=logging.DEBUG if verbose else logging.INFO,
                        format="tabletop: %(levelname)s: %(message)s")


def _context(cfg: dict[str, Any]) -> BuildContext:
    table = (cfg["table"]["width"], cfg["table"]["height"])
    base = Path(cfg.get("_base", "."))
    return BuildContext(table=table, rate_hz=cfg["loop"]["rate_hz"], config=cfg, base=base)


def build_tracker(cfg: dict[str, Any], ctx: BuildContext):
    """The configured puck tracker, or the pass-through one when no tracking plugin is installed."""
    tracking = registry.optional_module("tabletop.plugins.tracking")
    if tracking is None:
        return LatestMeasurements()
    return tracking.build_tracker(cfg["tracking"], ctx)


def build_engines(cfg: dict[str, Any], ctx: BuildContext) -> list[Engine]:
    return [registry.plugin_module("engine", e["kind"]).build(e, ctx) for e in cfg["engines"]]


def projector_homography(cfg: dict[str, Any], ctx: BuildContext):
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
                stop: threading.Event, view: bool = True) -> list[Sink]:
    sinks: list[Sink] = []
    if view and cfg["view"]["enabled"]:
        from tabletop.view import ProjectorView
        sinks.append(ProjectorView(ctx.table, cfg["view"], stats=stats, commands=commands,
                                   stop=stop, headless=headless,
                                   homography=projector_homography(cfg, ctx)))
        if cfg["view"]["calibration_check"]:
            from tabletop.live_check import live_check
            sinks.append(live_check(cfg, sinks[-1], ctx.shared.get("sources", ())))
    for s in cfg["sinks"]:
        sinks.append(registry.plugin_module("sink", s["kind"]).build(s, ctx))
    rec = cfg["recorder"]
    if record_path is None and rec["enabled"]:
        stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
        record_path = rec["path"] or Path(rec["folder"]) / f"session-{stamp}.jsonl"
    if record_path is not None:
        from tabletop.recorder import Recorder
        sinks.append(Recorder(record_path, config=cfg,
                              calibration=ctx.shared.get("calibration_dict")))
    return sinks


def build_live(cfg: dict[str, Any], headless: bool = False, record_path: Path | None = None,
               stats: LoopStats | None = None) -> Installation:
    """A live installation from a validated config: sources, tracker, engines, view, recorder."""
    ctx = _context(cfg)
    stats, commands, stop = stats or LoopStats(), CommandQueue(), threading.Event()
    ctx.shared.update(stats=stats, commands=commands, stop=stop)
    tracker = build_tracker(cfg, ctx)
    ctx.shared["tracker"] = tracker
    sources = [registry.plugin_module("source", s["kind"]).build(s, ctx) for s in cfg["sources"]]
    ctx.shared["sources"] = sources
    engines = build_engines(cfg, ctx)
    sinks = build_sinks(cfg, ctx, headless, record_path, stats, commands, stop)
    loop = Loop(LiveInputs(sources, tracker), engines, sinks, rate_hz=cfg["loop"]["rate_hz"],
                stats=stats, commands=commands, stop=stop)
    return Installation(loop, ctx, engines, sinks)


def build_replay(cfg: dict[str, Any], frames: Iterator, fast: bool, headless: bool = False,
                 record_path: Path | None = None, view: bool = True) -> Installation:
    """Recorded frames fed through the engines and sinks of the recorded config."""
    ctx = _context(cfg)
    stats, commands, stop = LoopStats(), CommandQueue(), threading.Event()
    ctx.shared.update(stats=stats, commands=commands, stop=stop)
    cfg = dict(cfg, recorder=dict(cfg["recorder"], enabled=False))
    engines = build_engines(cfg, ctx)
    sinks = build_sinks(cfg, ctx, headless, record_path, stats, commands, stop, view=view)
    loop = Loop(FrameInputs(frames, honour_times=not fast), engines, sinks,
                rate_hz=cfg["loop"]["rate_hz"], stats=stats, commands=commands, stop=stop,
                paced=False)
    return Installation(loop, ctx, engines, sinks)


@contextmanager
def stop_on_signals(stop: threading.Event) -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM set ``stop`` instead of killing the process."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum: int, _frame: Any) -> None:
        log.info("%s received: stopping", signal.Signals(signum).name)
        stop.set()

    old = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)
