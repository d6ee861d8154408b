"""Kiosk benchmark: how long the supervisor takes to have the table back, and what a durable
recording costs.

Recovery: the supervisor runs a small installation (scripted pucks, one reactor, headless
view) with the drill engine crashing it (SIGABRT in an engine) ``after_s`` into every even start
and freezing its frame loop ``after_s`` into every odd one (``after_s`` cycles through 0.5, 1
and 2 s: a failure soon after a restart finds spares still preparing). Each child runs longer
than ``healthy_s`` (0.3 s here), so every restart is immediate, as after a first failure (a
second failure in a row would wait ``backoff_s[0]``, 0.1 s, more). Measured: from the crash (the
child's death) or the stall's detection (no frame for ``stall_s`` = 1 s) to the new
installation's READY. Compared, interleaved A B C A B C: two warm spares (the default), one,
none. Budget (issue 15): back within 2 s.

Recording: frames of a 16-puck table handed over at 60 Hz for ``REC_S`` seconds, interleaved
A B C: the recorder (the frame loop serialises the frame and enqueues the line; a writer
thread writes and fdatasyncs each line before the next), the previous recorder's work on the loop (serialise,
write, flush to the operating system; synced twice a second elsewhere), and durable lines
written on the loop (serialise, write, fdatasync). Measured: the frame loop's cost per frame,
and each line's durability latency with the recorder (handed over -> fdatasync returned), on
the repository's disk.
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402
import yaml  # noqa: E402

from bench.common import emit, stats_ms  # noqa: E402
from tabletop.frames import Frame, Puck  # noqa: E402
from tabletop.kiosk.supervisor import Policy, Supervisor  # noqa: E402
from tabletop.recorder import Recorder  # noqa: E402
from tabletop.session import frame_to_dict  # noqa: E402

CHUNKS = 2              # supervisor runs per configuration, interleaved A B C A B C
CYCLES = 4              # crash + stall cycles per run
AFTER_S = (0.5, 1.0, 2.0)
STALL_S = 1.0
BACKOFF_S = (0.1, 2.0)
HEALTHY_S = 0.3
SPARES = {"two_spares": 2, "one_spare": 1, "no_spare": 0}     # two: the default
REC_ROUNDS = 3
REC_S = 3.0


def one_run(spares: int, cycles: int) -> tuple[list[float], list[float], list[bool]]:
    """One supervisor run: start 2k crashes, start 2k+1 stalls, each ``after_s`` into its run.
    Returns seconds from each crash and each detected stall to the next READY, and whether
    each restart was a prepared spare."""
    faults = [{"start": k, "after_s": AFTER_S[(k // 2) % len(AFTER_S)],
               "kind": "crash" if k % 2 == 0 else "stall"} for k in range(2 * cycles)]
    with tempfile.TemporaryDirectory() as d:
        cfg = Path(d) / "config.yaml"
        cfg.write_text(yaml.safe_dump({
            "loop": {"rate_hz": 30},
            "sources": [{"kind": "scripted", "pucks": [1, 2]}],
            "engines": [{"kind": "puppet_master", "name": "lover", "main": {"puck": 1},
                         "behavior": str(ROOT / "behaviors" / "library" / "lover")},
                        {"kind": "fault", "name": "drill", "faults": faults}],
            "view": {"size": [320, 180], "headless": True},
            "kiosk": {"heartbeat": {"enabled": False}},
        }))
        sup = Supervisor([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                          "--kiosk", "--headless"],
                         Policy(stall_s=STALL_S, backoff_s=BACKOFF_S, healthy_s=HEALTHY_S),
                         Path(d) / "crashes.log", echo=False, spares=spares)
        th = threading.Thread(target=sup.run)
        th.start()
        end = time.monotonic() + 150
        while time.monotonic() < end and \
                [e for e, _ in sup.events].count("ready") < 2 * cycles + 1:
            time.sleep(0.02)
        sup.stop.set()
        th.join(60)
    ev = sup.events
    kinds = [e for e, _ in ev]
    assert kinds == ["ready"] + ["crash", "ready", "stall", "ready"] * cycles, kinds
    crash = [ev[i + 1][1] - ev[i][1] for i in range(len(ev) - 1) if ev[i][0] == "crash"]
    stall = [ev[i + 1][1] - ev[i][1] for i in range(len(ev) - 1) if ev[i][0] == "stall"]
    return crash, stall, sup.warm[1:]


def recovery() -> dict:
    got: dict[str, tuple[list, list, list]] = {k: ([], [], []) for k in SPARES}
    for _ in range(CHUNKS):
        for name, spares in SPARES.items():
            for acc, xs in zip(got[name], one_run(spares, CYCLES)):
                acc.extend(xs)
    figures = {}
    for name, (crash, stall, warm) in got.items():
        figures[f"{name}_crash_to_ready_s_median"] = round(statistics.median(crash), 3)
        figures[f"{name}_crash_to_ready_s_max"] = round(max(crash), 3)
        figures[f"{name}_stall_detected_to_ready_s_median"] = round(statistics.median(stall), 3)
        figures[f"{name}_stall_detected_to_ready_s_max"] = round(max(stall), 3)
        figures[f"{name}_crash_to_ready_s_all"] = [round(x, 3) for x in crash]
        figures[f"{name}_stall_detected_to_ready_s_all"] = [round(x, 3) for x in stall]
        figures[f"{name}_restarts_warm"] = sum(warm)
        figures[f"{name}_restarts"] = len(warm)
    figures.update(runs_per_configuration=CHUNKS, cycles_per_run=CYCLES, after_s=list(AFTER_S),
                   backoff_s=list(BACKOFF_S), healthy_s=HEALTHY_S, stall_s=STALL_S)
    return figures


def frames(n: int, pucks: int = 16) -> list[Frame]:
    rng = np.random.default_rng(3)
    xy = rng.uniform(0.05, 0.5, size=(n, pucks, 3))
    return [Frame(seq=i, t=1000.0 + i / 60,
                  pucks=tuple(Puck(k, float(x), float(y), float(a))
                              for k, (x, y, a) in enumerate(xy[i])))
            for i in range(n)]


class OnLoop:
    """The alternatives, on the frame loop: each line serialised, written and flushed to the
    operating system (the recorder before; it synced twice a second in a thread), and also
    fdatasynced (durable line by line, on the loop)."""

    def __init__(self, path: Path, sync: bool) -> None:
        rec = Recorder(path, config={"loop": {"rate_hz": 60}})
        rec.close()               # its header; the lines are written here
        self.f, self.sync = open(path, "ab"), sync

    def consume(self, frame: Frame) -> None:
        d = frame_to_dict(frame, 1000.0)
        self.f.write((json.dumps(d, separators=(",", ":"), allow_nan=False) + "\n").encode())
        self.f.flush()
        if self.sync:
            os.fdatasync(self.f.fileno())

    def close(self) -> None:
        self.f.close()


def recording() -> dict:
    n = int(REC_S * 60)
    fs = frames(n)
    loop_s: dict[str, list[float]] = {"writer_thread": [], "flush_on_loop": [],
                                      "sync_on_loop": []}
    latency: list[float] = []
    per_sync: list[float] = []
    with tempfile.TemporaryDirectory(dir=ROOT) as d:   # the repository's disk, not a tmpfs
        for r in range(REC_ROUNDS):
            for name in loop_s:
                path = Path(d) / f"{name}-{r}.jsonl"
                rec = Recorder(path, config={"loop": {"rate_hz": 60}}) if name == "writer_thread" \
                    else OnLoop(path, sync=name == "sync_on_loop")
                t_next = time.perf_counter()
                for f in fs:
                    t0 = time.perf_counter()
                    rec.consume(f)
                    loop_s[name].append(time.perf_counter() - t0)
                    t_next += 1 / 60
                    time.sleep(max(0.0, t_next - time.perf_counter()))
                rec.close()
                if name == "writer_thread":
                    latency += rec.durability.latencies_s
                    per_sync.append(rec.durability.lines / max(1, rec.durability.syncs))
    out = {}
    for name, xs in loop_s.items():
        s = stats_ms(xs)
        out[f"{name}_frame_loop_ms_median"] = round(s["median_ms"], 4)
        out[f"{name}_frame_loop_ms_p99"] = round(s["p99_ms"], 4)
        out[f"{name}_frame_loop_ms_max"] = round(max(xs) * 1e3, 3)
    s = stats_ms(latency)
    out["line_durable_ms_median"] = round(s["median_ms"], 3)
    out["line_durable_ms_p99"] = round(s["p99_ms"], 3)
    out["line_durable_ms_max"] = round(max(latency) * 1e3, 3)
    out["lines_per_sync_mean"] = round(statistics.mean(per_sync), 3)
    out.update(rec_rounds=REC_ROUNDS, rec_frames_per_round=n, rec_pucks=16, rec_rate_hz=60)
    return out


def main() -> None:
    figures = recording()
    figures.update(recovery())
    emit("kiosk", figures, {"two_spares_crash_to_ready_s_max": 2.0,
                            "two_spares_stall_detected_to_ready_s_max": 2.0,
                            "line_durable_ms_p99": 1000 / 60})


if __name__ == "__main__":
    main()
