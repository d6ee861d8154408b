"""The main loop: one frame per tick, increasing seq and times, no pile-up behind a slow sink
(its pacing by the camera's frames: test_loop_pacing.py)."""

import math
import threading
import time

import pytest

from tabletop.frames import CharacterState, Frame, Observation, PuckMeasurement, SourceHealth
from tabletop.loop import CommandQueue, LatestMeasurements, LiveInputs, Loop
from tabletop.plugins.scripted import ScriptedSource
from tracking.visitor import ScriptedVisitor


class Collect:
    """A recording sink that keeps every frame it is given, optionally slow."""

    name = "collect"

    def __init__(self, delay: float = 0.0) -> None:
        self.frames: list[Frame] = []
        self.consumed_at: list[float] = []
        self.delay = delay
        self.closed = False

    def consume(self, frame: Frame) -> None:
        if self.delay:
            time.sleep(self.delay)
        self.frames.append(frame)
        self.consumed_at.append(time.monotonic())

    def close(self) -> None:
        self.closed = True


class CountingSource:
    """A source in its own thread producing observations at ``hz``, keeping only the newest."""

    def __init__(self, hz: float) -> None:
        self.name, self.hz = "counting", hz
        self.produced = 0
        self.published: list[tuple[float, float]] = []
        self._latest: Observation | None = None
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self.closed = False

    def open(self) -> None:
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(1.0 / self.hz):
            t = time.monotonic()
            self.produced += 1
            obs = Observation(self.name, t, self.produced,
                              pucks=(PuckMeasurement(7, 0.1 * self.produced, 0.2, 0.0, t),))
            with self._lock:
                self._latest = obs
            self.published.append((t, time.monotonic()))   # (capture time, when readable)

    def latest(self) -> Observation | None:
        with self._lock:
            return self._latest

    def health(self) -> SourceHealth:
        return SourceHealth(self.name, True)

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self.closed = True


def scripted_loop(sinks, engines=(), rate=120.0) -> Loop:
    src = ScriptedSource("visitor", ScriptedVisitor((1.2, 0.8), (1, 2), seed=1))
    return Loop(LiveInputs([src], LatestMeasurements()), list(engines), sinks, rate_hz=rate)


def test_n_ticks_make_n_frames_with_rising_seq_and_time():
    sink = Collect()
    ran = scripted_loop([sink]).run(max_ticks=50)
    assert ran == 50 and len(sink.frames) == 50
    assert [f.seq for f in sink.frames] == list(range(50))
    ts = [f.t for f in sink.frames]
    assert all(b > a for a, b in zip(ts, ts[1:]))
    assert all(len(f.pucks) == 2 for f in sink.frames)
    assert sink.closed


def test_fixed_rate_is_kept():
    """Ticks come one a slot of 1/50 s: judged on what ran, the slots the run lasted against
    the ticks plus the slots skipped (a loaded machine skips slots, it does not shift them).

    Tick k starts no earlier than its slot, start + (k + slots skipped before it) / rate, and
    after each tick the loop skips every slot that has already passed by more than a period
    (the last tick's included), so with n ticks and s skipped slots, exactly:
    (n + s - 1) / rate <= ran_s (not faster than the rate), and every frame lies within
    (n + s + 1) / rate of the start (not slower: no slot lost uncounted). Two ticks stall for
    3.5 periods, as a busy machine's would: their slots are skipped and the bounds still hold."""

    class Stalling(Collect):
        def consume(self, frame: Frame) -> None:
            self.delay = 0.07 if frame.seq in (10, 25) else 0.0
            super().consume(frame)

    sink = Stalling()
    loop = scripted_loop([sink], rate=50.0)
    n = loop.run(max_ticks=40)
    slots = n + loop.stats.skipped
    assert n == len(sink.frames) == 40 and loop.stats.skipped >= 2 * 2
    assert loop.ran_s >= (slots - 1) / 50.0
    first_start = sink.frames[0].t   # each frame's time is read during its tick, after start
    assert (loop.stats.tick_times[-1] - first_start) * 50.0 <= slots + 1


def test_slow_sink_does_not_pile_up_frames():
    """A sink taking 3 periods per frame: ticks are skipped, not made up for, and each frame
    carries the newest input there was when its tick began (nothing queues). Judged on what
    ran (the sink's own times, the source's publications, the loop's count), so a loaded
    machine that stretches the sleeps changes the figures, not the verdict."""
    source = CountingSource(hz=200.0)
    sink = Collect(delay=0.05)
    loop = Loop(LiveInputs([source], LatestMeasurements()), [], [sink], rate_hz=60.0)
    ran = loop.run(seconds=1.0)
    n = len(sink.frames)
    assert ran == n >= 3 and loop.ran_s >= 1.0
    # every tick took at least the sink's 3 periods (n <= run / 50 ms) and the other slots
    # were skipped, not made up for: ticks + skipped slots = the slots the run lasted
    assert n <= loop.ran_s / 0.05
    assert loop.stats.skipped >= 2 * n - 2
    assert n + loop.stats.skipped <= loop.ran_s * 60.0 + 1
    # the newest input: every observation published before the previous frame's sink was done
    # (so before this frame's tick began) is at most as new as this frame's
    published = list(source.published)
    for prev_done, f in zip(sink.consumed_at, sink.frames[1:]):
        before = [t for t, at in published if at < prev_done]
        assert f.t >= max(before, default=-math.inf)
    assert source.closed
    assert len(published) > n   # the source ran faster than the sink: there was a choice


def test_engines_run_in_order_and_see_earlier_characters():
    class Follower:
        def __init__(self, name, target):
            self.name, self.target = name, target

        def step(self, frame):
            if self.target is None:
                p = frame.puck(1)
                return (CharacterState(self.name, p.x, p.y, 0.0),)
            c = frame.character(self.target)
            return (CharacterState(self.name, c.x + 0.1, c.y, 0.0),)

    sink = Collect()
    scripted_loop([sink], [Follower("a", None), Follower("b", "a")]).run(max_ticks=5)
    f = sink.frames[-1]
    assert f.character("b").x == pytest.approx(f.character("a").x + 0.1)


def test_a_failing_engine_does_not_stop_the_installation():
    class Broken:
        name = "broken"
        calls = 0

        def step(self, frame):
            Broken.calls += 1
            if Broken.calls > 2:
                raise RuntimeError("boom")
            return (CharacterState("b", 0.5, 0.5, 0.0),)

    sink = Collect()
    loop = scripted_loop([sink], [Broken()])
    assert loop.run(max_ticks=10) == 10
    assert loop.stats.errors["engine broken"] == 8
    # the last good characters are kept on screen
    assert sink.frames[-1].character("b") is not None


def test_commands_reach_the_next_frame_once():
    q = CommandQueue()
    sink = Collect()
    loop = scripted_loop([sink])
    loop.commands = q
    loop.inputs.open()
    loop.tick()
    q.put("designer.record")
    loop.tick()
    loop.tick()
    assert [f.commands for f in sink.frames] == [(), ("designer.record",), ()]


def test_tab_moves_the_designer_focus_across_engines_and_commands_follow_it():
    class Designer:
        def __init__(self, name, parts):
            self.name, self.parts, self.seen = name, parts, []

        def designer_targets(self):
            return tuple(f"{self.name}/{p}" for p in self.parts) if self.parts else (self.name,)

        def step(self, frame):
            self.seen.append((frame.focus, frame.commands))
            return ()

    a, b = Designer("pm", ()), Designer("mop", ("face", "bird"))
    loop = scripted_loop([Collect()], [a, b])
    loop.inputs.open()
    script = [(), ("designer.record",), ("designer.next",), ("designer.next", "designer.keep"),
              ("designer.next",), ("designer.next",)]
    for cmds in script:
        for c in cmds:
            loop.commands.put(c)
        loop.tick()
    assert [f for f, _ in a.seen] == ["pm", "pm", "mop/face", "mop/bird", "pm", "mop/face"]
    assert [c for _, c in a.seen] == [(), ("designer.record",), (), ("designer.keep",), (), ()]
    assert b.seen == a.seen  # every engine sees the same frame; each acts on its own focus


def test_no_designer_targets_means_no_focus():
    sink = Collect()
    scripted_loop([sink]).run(max_ticks=3)
    assert all(f.focus is None for f in sink.frames)


class AnnouncingSource(CountingSource):
    """A camera-like source: observations at ``hz`` starting ``phase`` seconds after opening,
    each announced through ``notify`` (set by the loop's inputs) once it is ready."""

    def __init__(self, hz: float, phase: float) -> None:
        super().__init__(hz)
        self.phase = phase
        self.notify = None
        self.announced: list[float] = []

    def _run(self) -> None:
        next_t = time.monotonic() + self.phase
        while not self._stop.wait(max(0.0, next_t - time.monotonic())):
            self._announce()
            next_t += 1.0 / self.hz

    def _announce(self) -> None:
        """A frame now: kept as the latest and announced to the loop."""
        t = time.monotonic()
        self.produced += 1
        with self._lock:
            self._latest = Observation(self.name, t, self.produced)
        self.announced.append(t)
        if self.notify is not None:
            self.notify(t)


def test_the_run_freezes_start_up_objects_and_sets_the_thread_switch_interval():
    import gc
    import sys
    seen = []
    before = sys.getswitchinterval()

    def hook(frame):
        seen.append((gc.get_freeze_count(), sys.getswitchinterval()))

    loop = scripted_loop([Collect()])
    loop.hooks.append(hook)
    loop.run(max_ticks=3)
    assert all(n > 1000 for n, _ in seen)  # the installation's objects left out of GC passes
    assert all(s == pytest.approx(Loop.switch_interval_s) for _, s in seen)
    assert gc.get_freeze_count() == 0 and sys.getswitchinterval() == before


def test_a_realtime_priority_holds_while_the_loop_runs_and_is_given_back(caplog):
    """``realtime_priority``: the loop's thread and the source threads it starts run SCHED_FIFO
    at that priority while it runs (where the system allows it; else one warning and the
    ordinary scheduler), and the loop's thread is ordinary again afterwards."""
    import os
    if not hasattr(os, "sched_setscheduler"):
        pytest.skip("no sched_setscheduler on this system")
    seen, in_source = [], []

    class Source(AnnouncingSource):
        def open(self):
            super().open()
            in_source.append(os.sched_getscheduler(self._thread.native_id))

    source = Source(hz=60.0, phase=0.0)
    loop = Loop(LiveInputs([source], LatestMeasurements()), [], [Collect()], rate_hz=60.0)
    loop.realtime_priority = 3
    loop.hooks.append(lambda frame: seen.append(
        (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority)))
    before = os.sched_getscheduler(0)
    loop.run(max_ticks=5)
    assert os.sched_getscheduler(0) == before and len(seen) == 5
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(3))
        os.sched_setscheduler(0, before, os.sched_param(0))
    except PermissionError:
        assert set(seen) == {(before, 0)} and "refused" in caplog.text
        return
    assert set(seen) == {(os.SCHED_FIFO, 3)} and in_source == [os.SCHED_FIFO]


def test_a_source_raising_on_every_tick_is_unhealthy_and_logged_sparingly(caplog):
    """A scripted visitor whose speed range runs backwards raises in latest(); it was logged
    with its stack on every tick (91 tracebacks in 3 s) and its health stayed good."""
    from tabletop.plugins.tracking import Tracker
    from tracking.pucks import TrackerSettings

    clock = [0.0]
    broken = ScriptedSource("broken", ScriptedVisitor((1.2, 0.8), [1], speed=(0.35, 0.08)),
                            clock=lambda: clock[0])
    good = ScriptedSource("good", ScriptedVisitor((1.2, 0.8), [2]), clock=lambda: clock[0])
    inputs = LiveInputs([broken, good], Tracker(TrackerSettings(smooth=False)))
    inputs.open()
    frames = []
    with caplog.at_level("ERROR", logger="tabletop"):
        for k in range(1, 1201):   # 20 s at 60 Hz
            clock[0] = k / 60
            frames.append(inputs.next(k, clock[0]))
    logged = [r for r in caplog.records if "source broken raised in latest()" in r.getMessage()]
    assert len(logged) == 2 and "(601 times so far)" in logged[1].getMessage()
    health = {h.name: h for h in frames[-1].health}
    assert not health["broken"].ok and health["good"].ok
    assert health["broken"].message == "failed: high - low < 0 (1170 times so far)"  # from 0.5 s
    assert {p.id for p in frames[-1].pucks} == {2}


def test_an_engine_failing_on_every_tick_for_hours_is_logged_sparingly(caplog):
    """Each failure is counted; its line (with the stack) comes at once, then after 10, 20, 40
    ... up to 600 s while it goes on: every 10 s before, 2,160 stacks in six hours, which
    rotated the kiosk's log (1 MB x 5) away in hours."""
    class Broken:
        name = "broken"

        def step(self, frame):
            raise RuntimeError("boom")

    now = [0.0]
    # no source: the engine fails on the empty table's frames as on any (a scripted visitor
    # walking the six hours was 60% of the test's CPU, 2.1-2.5 -> 0.9-1.0 s)
    loop = Loop(LiveInputs([], LatestMeasurements()), [Broken()], [Collect()],
                clock=lambda: now[0], paced=False)
    loop.inputs.open()
    hours = 6 * 3600
    with caplog.at_level("ERROR", logger="tabletop"):
        for k in range(hours):                  # one tick a second of the loop's clock
            now[0] = float(k)
            loop.tick()
    lines = [r.getMessage() for r in caplog.records if "engine broken failed" in r.getMessage()]
    assert loop.stats.errors["engine broken"] == hours
    # at 0, 10, 30, 70, 150, 310, 630 s, then every 600 s
    assert len(lines) == 7 + (hours - 1 - 630) // 600 == 41
    assert "(1 times so far)" in lines[0] and "(11 times so far)" in lines[1]
