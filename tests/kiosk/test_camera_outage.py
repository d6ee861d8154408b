"""A camera that vanishes for 5 s: frames keep being rendered (the calm "one moment" screen),
and tracking resumes by itself when it is back."""

import dataclasses
import threading
import time

import yaml

from tabletop.config import load_config
from tabletop.kiosk.runner import Runner
from tracking.camera import InputLost
from tracking.scenes import wait_for


class Collect:
    name = "collect"

    def __init__(self):
        self.rows = []       # (wall time, frame status, pucks seen, camera healthy)

    def consume(self, frame):
        self.rows.append((time.monotonic(), frame.status,
                          sum(p.state == "seen" for p in frame.pucks),
                          all(h.ok for h in frame.health if h.name == "camera")))

    def close(self):
        pass


def _wakes(stop: threading.Event, every_s: float = 0.01) -> list[float]:
    """Wall times (monotonic s) at which a thread asking to wake every ``every_s`` woke, until
    ``stop``: its longest gap is how long this process could not run a thread (a loaded
    machine, the interpreter's lock held), a stall no loop of its own could avoid."""
    wakes: list[float] = []

    def run():
        while not stop.wait(every_s):
            wakes.append(time.monotonic())
    threading.Thread(target=run, daemon=True).start()
    return wakes


def _largest_gap(times: list[float], start: float, end: float) -> float:
    """The longest time from ``start`` to ``end`` (monotonic s) with none of ``times``."""
    edges = [start, *(t for t in times if start <= t < end), end]
    return max(b - a for a, b in zip(edges, edges[1:]))


def test_camera_lost_for_five_seconds(tmp_path):
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "synthetic_camera", "name": "camera", "pucks": [1, 2],
                     "resolution": [640, 360], "fps": 30, "hands": {"every_s": 0}}],
        "view": {"size": [320, 180], "headless": True},
        "kiosk": {"heartbeat": {"enabled": False}, "grace_s": 0.5},
    }))
    runner = Runner(cfg_path, load_config(cfg_path), headless=True, kiosk=True)
    inst = runner._build(runner.cfg)
    camera = inst.loop.inputs.sources[0]
    camera.settings = dataclasses.replace(camera.settings, retry_max_s=1.0)
    unplugged = threading.Event()
    opener = camera.opener

    def unplug_aware(settings):
        if unplugged.is_set():
            raise InputLost("camera unplugged")
        reader = opener(settings)
        read = reader.read

        def read_or_fail():
            if unplugged.is_set():
                raise InputLost("camera unplugged")
            return read()
        reader.read = read_or_fail
        return reader

    camera.opener = unplug_aware
    sink = Collect()
    inst.loop.sinks.insert(0, sink)
    view = next(s for s in inst.loop.sinks if s.name == "view")
    drawn = []
    consume = view.consume
    view.consume = lambda f: (drawn.append(f.status), consume(f))
    th = threading.Thread(target=inst.loop.run, kwargs={"seconds": 20})
    th.start()
    done = threading.Event()
    wakes = _wakes(done)
    try:
        assert wait_for(lambda: sink.rows and sink.rows[-1][2] == 2, 10.0)
        t_unplug = time.monotonic()
        unplugged.set()
        time.sleep(5.0)
        t_back = time.monotonic()
        unplugged.clear()
        assert wait_for(lambda: sink.rows[-1][1] == "" and sink.rows[-1][2] == 2, 10.0)
    finally:
        inst.loop.stop.set()
        done.set()
        th.join(10)
    during = [r for r in sink.rows if t_unplug <= r[0] < t_back]
    # Frames kept coming through the outage, not counted against the 30 Hz rate (a loaded
    # machine skips ticks): no wait of the camera's (its reopening: 0.5 to 1 s back-offs, on
    # its own thread) holds the loop: its longest time without a frame (from the unplugging to
    # the return) stays under 0.5 s, beyond the longest time the process itself stood still
    # (a 0.517 s gap under a load of 12 on 2 cores; 40-70 ms with six busy loops, 37 ms idle).
    # A loop waiting out a back-off sleeps with the interpreter free, so the waking thread
    # shows no such stall to excuse it.
    stalled = _largest_gap(wakes, t_unplug, t_back)
    assert _largest_gap([r[0] for r in during], t_unplug, t_back) < 0.5 + stalled
    # "one moment" once the camera has been down for the 0.5 s grace by the filter's clock,
    # which reads each frame after the previous row's sink time and before its own: its
    # down-since reading (row d, the first frame showing the camera down) lies between the
    # times of rows d-1 and d, and each row is judged only where that bracket decides it
    down = [i for i, r in enumerate(sink.rows) if r[0] >= t_unplug and not r[3]]
    d = down[0]
    stretch = down[:next((j for j, (a, b) in enumerate(zip(down, down[1:])) if b != a + 1),
                         len(down) - 1) + 1]                      # down without a break
    rows = sink.rows
    waiting = [rows[k] for k in stretch[1:] if rows[k - 1][0] >= rows[d][0] + 0.5]
    early = [rows[k] for k in stretch if rows[k][0] < rows[d - 1][0] + 0.5]
    assert waiting and all(r[1] == "one_moment" for r in waiting), waiting
    assert all(r[1] == "" for r in early), early      # (none if a tick came that late)
    assert drawn.count("one_moment") >= len(waiting)        # the view drew the calm screen
    after = [r for r in sink.rows if r[0] > t_back]
    assert after[-1][2] == 2 and camera.reconnects >= 1
