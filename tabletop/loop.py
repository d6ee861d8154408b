"""The main loop: one immutable Frame per tick, built from the newest input, stepped through the
engines in order and handed to every sink.

Stage order per tick: inputs (sources' newest observations fused by the tracker, or a recording's
next frame) -> operator commands -> engines (in config order, each seeing the characters of the
ones before) -> sinks. Sources run in their own threads and hold only their newest observation;
the loop never queues frames, so a slow sink makes the loop skip ticks, never pile them up.
Paced, it ticks as soon as a camera frame has been measured (not at the next timer slot), so
capture-to-render is the frame's measuring plus one tick.
Strict at start-up, forgiving at run time: an engine or sink that raises is logged (rate-limited)
and the installation keeps running.
"""

from __future__ import annotations

import collections
import dataclasses
import gc
import logging
import math
import sys
import threading
import time
from typing import Any, Callable, Sequence

from tabletop.frames import CharacterState, Engine, Frame, Sink
# Live inputs live in tabletop.live_inputs; their names are kept importable here.
from tabletop.live_inputs import LatestMeasurements, LiveInputs  # noqa: F401
from tabletop.loop_stats import LoopStats
from tabletop.realtime import realtime_threads
from tabletop.replay_inputs import FrameInputs  # noqa: F401  (replays; kept importable here)
from tracking.badinput import LogGaps

log = logging.getLogger("tabletop")


class CommandQueue:
    """Operator commands (key presses, markers) from sinks to the next tick; bounded,
    thread-safe."""

    def __init__(self, maxlen: int = 64) -> None:
        self._q: collections.deque[str] = collections.deque(maxlen=maxlen)
        self._lock = threading.Lock()

    def put(self, command: str) -> None:
        with self._lock:
            self._q.append(command)

    def drain(self) -> tuple[str, ...]:
        with self._lock:
            out = tuple(self._q)
            self._q.clear()
        return out


class DesignerFocus:
    """Which designer target operator commands address: ``designer.next`` (Tab) cycles through
    the targets of every engine in order; the frame carries the choice in ``focus``."""

    def __init__(self, engines: Sequence[Engine]) -> None:
        self.engines = engines
        self.extra: list = []      # more providers of designer_targets (the studio)
        self.focus: str | None = None

    def targets(self) -> list[str]:
        out: list[str] = []
        for e in [*self.extra, *self.engines]:
            fn = getattr(e, "designer_targets", None)
            if fn is not None:
                out.extend(fn())
        return out

    def apply(self, commands: tuple[str, ...],
              recorded: str | None = None) -> tuple[tuple[str, ...], str | None]:
        """(commands without ``designer.next``, the focus after them); with one designer target
        and a ``designer.next`` among them, ``designer.only_target`` is added (the studio says
        Tab has nowhere to go). A replayed frame's ``recorded`` focus is kept as it was and
        nothing is added (the studio's recorded commands hold any ``only_target``)."""
        if recorded is not None:
            self.focus = recorded
            return tuple(c for c in commands if c != "designer.next"), recorded
        targets = self.targets()
        if not targets:
            self.focus = None
            return commands, None
        if self.focus not in targets:
            self.focus = targets[0]
        for _ in range(commands.count("designer.next")):
            self.focus = targets[(targets.index(self.focus) + 1) % len(targets)]
        out = tuple(c for c in commands if c != "designer.next")
        if len(targets) == 1 and len(out) < len(commands):
            out += ("designer.only_target",)    # Tab with nowhere to go: the studio says so
        return out, self.focus


class Loop:
    """Runs the installation at ``rate_hz``: inputs -> commands -> engines -> sinks, once a tick."""

    freeze_gc = True          # keep start-up objects out of the garbage collector's passes
    FREEZE_AGAIN_TICKS = 120  # ... and what the first ticks made
    # Python's interpreter lock passes to a waiting thread only after this long (5 ms by
    # default): the loop woken by a camera frame while the camera thread goes on rendering or
    # detecting in Python waited 8 ms (median) for it; with 1 ms, 1.2 ms. None: left as it is.
    switch_interval_s: float | None = 0.001
    # 1-99: while paced, every thread of the process (and those started later: cameras) runs
    # with this SCHED_FIFO priority, ahead of every ordinary program (see realtime.py).
    realtime_priority = 0

    def __init__(self, inputs: LiveInputs | FrameInputs, engines: Sequence[Engine],
                 sinks: Sequence[Sink], rate_hz: float = 60.0, stats: LoopStats | None = None,
                 commands: CommandQueue | None = None, stop: threading.Event | None = None,
                 clock: Callable[[], float] = time.monotonic, paced: bool = True,
                 filters: Sequence[Callable[[Frame], Frame]] = (),
                 hooks: Sequence[Callable[[Frame], None]] = ()) -> None:
        self.inputs, self.engines, self.sinks = inputs, list(engines), list(sinks)
        # filters: frame -> frame after the inputs, before the engines (attract mode, "one
        # moment"); hooks: called with the completed frame after the sinks (health, watchdog
        # pings, file watchers). Both run in the frame loop itself.
        self.filters, self.hooks = list(filters), list(hooks)
        self.period = 1.0 / rate_hz
        self.stats = stats or LoopStats()
        self.commands = commands or CommandQueue()
        self.stop = stop or threading.Event()
        self.clock, self.paced = clock, paced
        self.focus = DesignerFocus(self.engines)
        self.seq = 0
        self.ran_s = 0.0   # seconds the last run() lasted, from its start to its stop (not closing)
        self._last_characters: dict[str, tuple[CharacterState, ...]] = {}
        self._last_ready_t = -math.inf
        self._tick_start: float | None = None   # clock time the previous tick started
        self._error_log = LogGaps()

    def _report(self, where: str) -> None:
        """Log an exception from a running part, sparingly (LogGaps) per part."""
        self.stats.errors[where] += 1
        if self._error_log.due(where, self.clock()):
            log.exception("%s failed (%d times so far); the installation keeps running",
                          where, self.stats.errors[where])

    def tick(self) -> Frame | None:
        """Run one tick; returns the completed frame, or None when the inputs are exhausted."""
        t0 = self._tick_start = self.clock()
        frame = self.inputs.next(self.seq, t0)
        if frame is None:
            return None
        t1 = self.clock()
        commands, focus = self.focus.apply(frame.commands + self.commands.drain(), frame.focus)
        if commands != frame.commands or focus != frame.focus:
            frame = dataclasses.replace(frame, commands=commands, focus=focus)
        for fn in self.filters:
            try:
                frame = fn(frame)
            except Exception:
                self._report(f"filter {getattr(fn, '__name__', type(fn).__name__)}")
        st = self.stats
        te = t1
        for engine in self.engines:
            try:
                produced = tuple(engine.step(frame))
                self._last_characters[engine.name] = produced
            except Exception:
                self._report(f"engine {engine.name}")
                produced = self._last_characters.get(engine.name, ())
            frame = frame.with_characters(produced)
            te, t_prev = self.clock(), te
            st.record(f"engine:{engine.name}", te - t_prev)
        t2 = self.clock()
        ts = t2
        shown: float | None = None   # when a sink that presents (the view) was done
        for sink in self.sinks:
            try:
                sink.consume(frame)
            except Exception:
                self._report(f"sink {sink.name}")
            ts, t_prev = self.clock(), ts
            st.record(f"sink:{sink.name}", ts - t_prev)
            if shown is None and getattr(sink, "presents", False):
                shown = ts
        for hook in self.hooks:
            try:
                hook(frame)
            except Exception:
                self._report(f"hook {getattr(hook, '__name__', type(hook).__name__)}")
        t3 = self.clock()
        st.record("inputs", t1 - t0)
        st.record("engines", t2 - t1)
        st.record("sinks", t3 - t2)
        st.record("tick", t3 - t0)
        if frame.t <= t3 and getattr(self.inputs, "live", True) and getattr(
                self.inputs, "captured", True):
            st.record("capture_age", (t3 if shown is None else shown) - frame.t)
            ready = getattr(self.inputs, "ready_time", None)
            ready = ready(frame.t) if ready is not None else None
            if ready is not None and frame.t != self._last_ready_t:  # once per observation
                self._last_ready_t = frame.t
                st.record("source", ready - frame.t)
                st.record("queued", max(0.0, t0 - ready))
        st.tick_times.append(t3)
        if st.first_t is None:
            st.first_t = frame.t
        st.ticks += 1
        self.seq += 1
        return frame

    def run(self, seconds: float | None = None, max_ticks: int | None = None) -> int:
        """Tick at the fixed rate until stopped, ``seconds`` elapsed, ``max_ticks`` ran or the
        inputs end. A late tick is not made up for: the schedule skips ahead. Returns ticks run.

        Paced, the loop follows inputs that announce their new observations (cameras): see
        :meth:`wait_for_slot`. Once the inputs are open, the objects made so far (plugins,
        models, caches) are frozen out of the garbage collector's passes, which would otherwise
        walk them all again now and then and stall a tick; and the interpreter lock is handed
        between threads every ``switch_interval_s``."""
        start = self.clock()
        next_t = start
        ran = 0
        restore = (realtime_threads(self.realtime_priority)
                   if self.realtime_priority and self.paced else None)
        try:
            self.inputs.open()   # its threads (cameras) inherit the priority
        except BaseException:
            if restore is not None:
                restore()
            raise
        if self.freeze_gc:
            gc.freeze()
        switch = sys.getswitchinterval()
        if self.switch_interval_s is not None:
            sys.setswitchinterval(self.switch_interval_s)
        try:
            while not self.stop.is_set():
                if seconds is not None and self.clock() - start >= seconds:
                    break
                if max_ticks is not None and ran >= max_ticks:
                    break
                if self.paced:
                    next_t, stopped = self.wait_for_slot(next_t)
                    if stopped:
                        break
                if self.tick() is None:
                    break
                ran += 1
                if ran == self.FREEZE_AGAIN_TICKS and self.freeze_gc:
                    gc.freeze()   # and what the first ticks made (caches, models' buffers)
                next_t += self.period
                behind = self.clock() - next_t
                if behind > self.period:
                    missed = int(behind / self.period)
                    self.stats.skipped += missed
                    next_t += missed * self.period
        finally:
            self.ran_s = self.clock() - start
            if restore is not None:
                restore()
            sys.setswitchinterval(switch)
            if self.freeze_gc:
                gc.unfreeze()  # what this run made may be collected again (a rebuilt installation)
            self.close()
        return ran

    def wait_for_slot(self, slot: float) -> tuple[float, bool]:
        """Wait for the tick planned at ``slot`` (clock seconds); returns (the slot the tick
        stands for, whether the loop was stopped meanwhile).

        Inputs that announce their new observations (``fresh``: cameras) and deliver them no
        faster than about the loop rate are followed: the tick runs as soon as a new observation
        arrives (at least a quarter period after the previous tick), so a frame does not wait
        for the timer, and the schedule moves to that moment. Without one it runs at its slot,
        or up to a period later when observations come about once a period (0.9 to 1.1
        periods apart: waiting for a late frame rather than drawing the old one again; the
        next is due by then). Faster inputs, and all others, tick at their slots (a plain timer).

        Measured against a wait of a quarter period for a late frame: on a loaded machine
        (frames later than that) the loop then draws the old capture again at that moment and
        the late one a quarter period after, a tick more per late frame: 66.8 ticks/s with a
        60 Hz loop and a 60 fps camera (load 11), 39 ticks for 31 frames in
        tests/tabletop/test_loop_pacing.py's every third frame 0.4 period late; waiting up to
        the period: a tick per frame. A silent camera still gets the timer within three of its
        intervals (:meth:`LiveInputs.arrival_interval`).
        """
        fresh: threading.Event | None = getattr(self.inputs, "fresh", None)
        p = self.period
        now = self.clock()
        interval = (self.inputs.arrival_interval(now) if fresh is not None
                    and self.clock is time.monotonic else 0.0)
        if interval < 0.9 * p or not getattr(self.inputs, "follow", False):
            return slot, slot > now and self.stop.wait(slot - now)
        earliest = (self._tick_start if self._tick_start is not None else now) + 0.25 * p
        latest = slot + (p if interval <= 1.1 * p else 0.0)
        while True:
            if self.stop.is_set():
                return slot, True
            now = self.clock()
            if now >= earliest and fresh.is_set():
                return min(now, slot + 0.5 * p), False  # a late wake-up keeps the schedule
            if now >= latest:
                return slot, False
            if fresh.is_set():
                self.stop.wait(earliest - now)
            else:
                fresh.wait(min(latest - now, 0.05))

    def close(self) -> None:
        """Close the inputs, then the sinks (so a recording is flushed complete), then the
        engines that hold something (``close()``: the touch-pose engine's pybullet world).
        Engines were left open: a kiosk rebuilt on every applied config edit kept each old
        physics world, about 40 MB resident per edit with the gallery soak's touch-pose.
        Filters with a ``close()`` are closed first (the studio logs a take left tried)."""
        _close_each(self.filters, "filter")
        self.inputs.close()
        _close_each(self.sinks, "sink")
        _close_each(self.engines, "engine")


def _close_each(parts: Sequence[Any], what: str) -> None:
    """``close()`` each part that has one; one that fails is logged and the next is closed."""
    for part in parts:
        close = getattr(part, "close", None)
        if close is None:
            continue
        try:
            close()
        except Exception:
            log.exception("%s %s failed to close", what, getattr(part, "name", part))
