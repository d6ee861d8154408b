"""Kiosk benchmark: how long the supervisor takes to have the table back, and what a durable
recording costs.

Recovery: each round runs the supervisor on a small installation (scripted pucks, one reactor,
headless view) with the drill engine crashing it (SIGABRT in an engine) ``after_s`` into its
first start and freezing its frame loop ``after_s`` into its second (``after_s`` cycles through
0.5, 1 and 2 s: a crash soon after a restart finds a spare still preparing). Measured: from the
crash (the child's death) or the stall's detection (no frame for ``stall_s`` = 1 s) to the new
installation's READY; the stall is the second failure in a row, so it waits ``backoff_s[0]``
(0.1 s) more. Compared, interleaved A B C A B A B A: two warm spares (the default, 5 rounds),
one (3) and none (1). Budget (issue 15): back within 2 s.

Recording: frames of a 16-puck table handed over at 60 Hz for ``REC_S`` seconds, interleaved
A B C: the recorder (the frame loop serialises, writes and flushes each line to the operating
system; a thread fdatasyncs as soon as lines are written), the same on the loop without any
sync, and durable lines written on the loop (serialise, write, fdatasync). Measured: the frame
loop's cost per frame, and each line's durability latency with the recorder (written ->
fdatasync returned), on the repository's disk.
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

from bench.common import check_flags, emit, stats_ms  # noqa: E402
from tabletop.frames import Frame, Puck  # noqa: E402
from tabletop.kiosk.supervisor import Policy, Supervisor  # noqa: E402
from tabletop.recorder import Recorder  # noqa: E402
from tabletop.session import frame_to_dict  # noqa: E402

ROUNDS = 5
SPARES = {"two_spares": 2, "one_spare": 1, "no_spare": 0}     # two: the default
SPARES_ROUNDS = {"two_spares": ROUNDS, "one_spare": 3, "no_spare": 1}
AFTER_S = (0.5, 1.0, 2.0)
STALL_S = 1.0
BACKOFF_S = (0.1, 2.0)
REC_ROUNDS = 3
REC_S = 3.0


def one_round(spares: int, after_s: float) -> tuple[float, float, bool, bool]:
    with tempfile.TemporaryDirectory() as d:
        cfg = Path(d) / "config.yaml"
        cfg.write_text(yaml.safe_dump({
            "loop": {"rate_hz": 30},
            "sources": [{"kind": "scripted", "pucks": [1, 2]}],
            "engines": [{"kind": "puppet_master", "name": "lover", "main": {"puck": 1},
                         "behavior": str(ROOT / "behaviors" / "library" / "lover")},
                        {"kind": "fault", "name": "drill", "faults": [
                            {"start": 0, "after_s": after_s, "kind": "crash"},
                            {"start": 1, "after_s": after_s, "kind": "stall"}]}],
            "view": {"size": [320, 180], "headless": True},
            "kiosk": {"heartbeat": {"enabled": False}},
        }))
        sup = Supervisor([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                          "--kiosk", "--headless"],
                         Policy(stall_s=STALL_S, backoff_s=BACKOFF_S), Path(d) / "crashes.log",
                         echo=False, spares=spares)
        th = threading.Thread(target=sup.run)
        th.start()
        end = time.monotonic() + 120
        while time.monotonic() < end and [e for e, _ in sup.events].count("ready") < 3:
            time.sleep(0.02)
        sup.stop.set()
        th.join(60)
    ev = sup.events
    kinds = [e for e, _ in ev]
    assert kinds[:5] == ["ready", "crash", "ready", "stall", "ready"], kinds
    return ev[2][1] - ev[1][1], ev[4][1] - ev[3][1], sup.warm[1], sup.warm[2]


def recovery() -> dict:
    got: dict[str, list[tuple[float, float, bool, bool]]] = {k: [] for k in SPARES}
    for i in range(ROUNDS):
        for name, spares in SPARES.items():
            if i >= SPARES_ROUNDS[name]:
                continue
            got[name].append(one_round(spares, AFTER_S[i % len(AFTER_S)]))
    figures = {}
    for name, rows in got.items():
        crash = [r[0] for r in rows]
        stall = [r[1] for r in rows]
        figures[f"{name}_crash_to_ready_s_median"] = round(statistics.median(crash), 3)
        figures[f"{name}_crash_to_ready_s_max"] = round(max(crash), 3)
        figures[f"{name}_stall_detected_to_ready_s_median"] = round(statistics.median(stall), 3)
        figures[f"{name}_stall_detected_to_ready_s_max"] = round(max(stall), 3)
        figures[f"{name}_crash_to_ready_s_all"] = [round(x, 3) for x in crash]
        figures[f"{name}_stall_detected_to_ready_s_all"] = [round(x, 3) for x in stall]
        figures[f"{name}_restarts_warm"] = sum(r[2] + r[3] for r in rows)
        figures[f"{name}_restarts"] = 2 * len(rows)
    figures.update(rounds={k: len(v) for k, v in got.items()}, after_s=list(AFTER_S),
                   backoff_s=list(BACKOFF_S), stall_s=STALL_S)
    return figures


def frames(n: int, pucks: int = 16) -> list[Frame]:
    rng = np.random.default_rng(3)
    xy = rng.uniform(0.05, 0.5, size=(n, pucks, 3))
    return [Frame(seq=i, t=1000.0 + i / 60,
                  pucks=tuple(Puck(k, float(x), float(y), float(a))
                              for k, (x, y, a) in enumerate(xy[i])))
            for i in range(n)]


class OnLoop:
    """The alternatives, all on the frame loop: each line serialised, written and flushed to the
    operating system with no sync, or also fdatasynced (durable line by line, the loop waiting
    for the disk). The recorder writes like the first and syncs in a thread."""

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
    loop_s: dict[str, list[float]] = {"recorder": [], "flush_on_loop": [],
                                      "sync_on_loop": []}
    latency: list[float] = []
    per_sync: list[float] = []
    with tempfile.TemporaryDirectory(dir=ROOT) as d:   # the repository's disk, not a tmpfs
        for r in range(REC_ROUNDS):
            for name in loop_s:
                path = Path(d) / f"{name}-{r}.jsonl"
                rec = Recorder(path, config={"loop": {"rate_hz": 60}}) if name == "recorder" \
                    else OnLoop(path, sync=name == "sync_on_loop")
                t_next = time.perf_counter()
                for f in fs:
                    t0 = time.perf_counter()
                    rec.consume(f)
                    loop_s[name].append(time.perf_counter() - t0)
                    t_next += 1 / 60
                    time.sleep(max(0.0, t_next - time.perf_counter()))
                rec.close()
                if name == "recorder":
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
    check_flags("kiosk", sys.argv[1:])
    figures = recording()
    figures.update(recovery())
    emit("kiosk", figures, {"two_spares_crash_to_ready_s_max": 2.0,
                            "two_spares_stall_detected_to_ready_s_max": 2.0,
                            "line_durable_ms_p99": 1000 / 60})


if __name__ == "__main__":
    main()
