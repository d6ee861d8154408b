"""The paced loop and its camera: a tick when a frame is announced, not at the timer's slot (late
frames waited for, a faster source not followed faster, a silent one leaving the timer), and
capture-to-render counted once per capture up to the view's presenting."""

import threading
import time

import pytest

from tabletop.loop import LatestMeasurements, LiveInputs, Loop
from tests.tabletop.test_loop import AnnouncingSource, Collect, scripted_loop


@pytest.mark.parametrize("follow", [True, False])
def test_the_paced_loop_ticks_when_a_frame_is_ready_not_at_its_timer(follow):
    """Frames at the loop's rate arriving half a period after its timer slots: followed, each
    tick takes a frame just announced (``queued`` well under the half period the timer makes it
    wait), every frame is drawn once, and the stages before the tick are recorded."""
    rate = 10.0
    source = AnnouncingSource(hz=rate, phase=0.05)
    sink = Collect()
    inputs = LiveInputs([source], LatestMeasurements())
    inputs.follow = follow
    loop = Loop(inputs, [], [sink], rate_hz=rate)
    loop.run(seconds=1.6)
    queued = list(loop.stats.samples["queued"])[3:] if follow else [
        c - f.t for f, c in zip(sink.frames, sink.consumed_at)][3:]
    queued.sort()
    median = queued[len(queued) // 2]
    if follow:
        assert median < 0.2 / rate  # the timer would have made each frame wait 0.5 / rate
        fresh = [f.t for f in sink.frames[3:]]
        assert len(set(fresh)) >= len(fresh) - 1  # no frame drawn twice (one miss allowed)
        assert len(loop.stats.samples["source"]) >= 10
    else:
        assert median > 0.3 / rate  # the plain timer: each frame waits for the next slot
        assert "queued" not in loop.stats.samples or not loop.stats.samples["queued"]


class LateSource(AnnouncingSource):
    """A camera at the loop's rate on a fixed grid whose every ``every``-th frame is announced
    ``late`` seconds after its slot (a loaded machine; the next frame is on time again)."""

    def __init__(self, hz: float, late: float, every: int = 3) -> None:
        super().__init__(hz, phase=0.0)
        self.late, self.every = late, every

    def _run(self) -> None:
        start = time.monotonic()
        k = 0
        while True:
            due = start + k / self.hz + (self.late if k % self.every == 1 else 0.0)
            if self._stop.wait(max(0.0, due - time.monotonic())):
                return
            self._announce()
            k += 1


def test_late_frames_do_not_make_the_loop_tick_faster_than_its_camera():
    """Every third frame 0.4 period late: the loop waits for it instead of drawing the old
    capture again at its timer slot and then the late one (a tick more per late frame, read as
    more fps than the loop's rate: 37 ticks for 28 frames); every frame is still drawn."""
    rate = 10.0
    source = LateSource(hz=rate, late=0.4 / rate)
    sink = Collect()
    loop = Loop(LiveInputs([source], LatestMeasurements()), [], [sink], rate_hz=rate)
    loop.run(seconds=3.0)
    after = source.announced[3]     # (the first frames: the timer, no interval known yet)
    frames = sum(1 for t in source.announced if t >= after)
    drawn = [f.t for f in sink.frames if f.t >= after]
    late = frames // 3     # a tick more for each before; half of them allowed (a loaded machine
    assert len(drawn) <= frames + late // 2        # wakes the camera a period late now and then)
    assert len(set(drawn)) >= frames - late // 2   # and the captures are drawn


def test_a_faster_source_keeps_the_loop_at_its_rate():
    """Observations announced at three times the loop rate do not make it tick faster."""
    source = AnnouncingSource(hz=90.0, phase=0.0)
    sink = Collect()
    loop = Loop(LiveInputs([source], LatestMeasurements()), [], [sink], rate_hz=30.0)
    loop.run(seconds=1.0)
    assert 20 <= len(sink.frames) <= 36
    assert len(source.announced) >= 60


def test_a_silent_announcing_source_leaves_the_timer_ticking():
    """A camera that announces nothing (unplugged) does not stop the loop: the timer ticks."""
    source = AnnouncingSource(hz=0.5, phase=5.0)
    sink = Collect()
    Loop(LiveInputs([source], LatestMeasurements()), [], [sink], rate_hz=40.0).run(seconds=0.5)
    assert len(sink.frames) >= 12 and not source.announced


def test_capture_to_render_ends_when_the_view_has_presented():
    """Work after the presenting sink (a recorder, hooks) is not part of capture-to-render; the
    tick still includes it."""

    class Presenter(Collect):
        presents = True

    loop = scripted_loop([Presenter(), Collect(delay=0.05)])
    loop.hooks.append(lambda frame: time.sleep(0.02))
    loop.run(max_ticks=8)
    ages, ticks = loop.stats.samples["capture_age"], loop.stats.samples["tick"]
    assert len(ages) == len(ticks) == 8 and min(ticks) >= 0.07
    # tick by tick, the 50 ms sink and the 20 ms hook after the view are outside its age (the
    # scripted capture is read at the tick's start; measured 70.3-77 ms apart, whatever the
    # load: sleeps only ever last longer); ended at the tick's end, under 0.01 ms apart
    gaps = [tick - age for tick, age in zip(ticks, ages)]
    assert min(gaps) >= 0.069, gaps


def test_capture_to_render_counts_each_capture_once_and_no_stalled_stamp():
    """A 30 Hz camera on the 60 Hz loop: each capture's latency is counted at its first drawing
    only (drawn again on the timer, it is no new capture), and while the camera is stalled the
    frames stamped ``STALE_S`` back are no capture either: the figure says how old a capture is
    when the visitor first sees it."""
    source = AnnouncingSource(hz=30.0, phase=0.0)
    sink = Collect()
    loop = Loop(LiveInputs([source], LatestMeasurements()), [], [sink], rate_hz=60.0)
    threading.Timer(0.6, source._stop.set).start()   # the camera stalls after 0.6 s

    def stalled_for_a_while(frame) -> None:   # 5 ticks stamped STALE_S back: enough
        if sum(f.t not in source.announced for f in sink.frames) >= 5:
            loop.stop.set()
    loop.hooks.append(stalled_for_a_while)
    loop.run(seconds=60.0)                          # (a liveness bound only)
    ages = list(loop.stats.samples["capture_age"])
    drawn = {f.t for f in sink.frames if f.t in source.announced}
    stamped = [f for f in sink.frames if f.t not in source.announced]
    assert len(stamped) == 5 and len(drawn) >= 2
    assert len(sink.frames) > len(drawn) + 5    # redrawn on the timer too (a 60 Hz loop)
    assert len(ages) == len(drawn)   # an age per drawing instead: 74 ages for 18 captures
