"""TUIO in over loopback UDP: loss and send-to-bus latency of 16-object bundles at 60 and 240 Hz.

A sender process sends reference-style ``/tuio/2Dobj`` bundles (source, alive, 16 sets, fseq)
to the ``osc`` source on 127.0.0.1 while the main loop runs beside it at 60 Hz (tracker, one
collecting sink), as in an installation. For every bundle, latency runs from just before
``sendto`` to the moment ``latest()`` returns an observation holding it (received, decoded,
committed and put on the bus), measured in the receiving thread; receive-to-bus is the part
after the datagram left the socket (decoding, the TUIO state, building the observation). Loss
counts bundles never committed. The two rates run interleaved in blocks (60 240 60 240 ...).

Also: microseconds to decode one such bundle and apply it to the TUIO state, against
python-osc's own parser (``OscPacket``) on the same bytes (interleaved).

Budget (DESIGN.md): no loss at 240 Hz, send-to-bus p99 <= 2 ms.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit, interleaved, stats_ms  # noqa: E402
from tabletop.loop import LiveInputs, Loop  # noqa: E402
from tabletop.plugins.tracking import Tracker  # noqa: E402
from tracking.osc_codec import decode_packet  # noqa: E402
from tracking.osc_input import OscInput  # noqa: E402
from tracking.tuio import TuioClient, profile_bundles  # noqa: E402

OBJECTS = 16
BLOCK_S = 6.0
ROUNDS = 4
RATES = (60, 240)
SOURCE = "bench@127.0.0.1"


def bundle(fseq: int, t: float) -> bytes:
    sets = []
    for i in range(OBJECTS):
        a = 0.3 * t + i
        sets.append(("set", i + 1, i, 0.5 + 0.3 * np.cos(a), 0.5 + 0.3 * np.sin(a), a % 6.28,
                     0.1, 0.1, 0.0, 0.0, 0.0))
    sets = [tuple(float(v) if isinstance(v, np.floating) else v for v in s) for s in sets]
    return profile_bundles("2Dobj", SOURCE, list(range(1, OBJECTS + 1)), sets, fseq)[0]


class Probe:
    """Called in the receiving thread after each packet: notes when each bundle is on the bus."""

    def __init__(self, src: OscInput) -> None:
        self.src = src
        self.on_bus: dict[int, float] = {}
        self.processing: dict[int, float] = {}

    def __call__(self, t_received: float) -> None:
        obs = self.src.latest()
        t = time.monotonic()
        sender = next((s for s in self.src.client.senders.values() if s.name == SOURCE), None)
        if obs is None or sender is None or len(obs.pucks) != OBJECTS:
            return
        fseq = sender.profiles["2Dobj"].fseq
        if fseq not in self.on_bus:
            self.on_bus[fseq] = t
            self.processing[fseq] = t - t_received


def send_block(port: int, rate: float, first: int, n: int, conn) -> None:
    """In a separate process (as a tracker machine would be): send ``n`` bundles at ``rate``
    and report the monotonic send time of each (the clock is shared by all processes)."""
    import socket

    period = 1.0 / rate
    packets = [bundle(first + k, k * period) for k in range(n)]
    sent = []
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        start = time.monotonic() + 0.05
        for k, p in enumerate(packets):
            wait = start + k * period - time.monotonic()
            if wait > 0:
                time.sleep(wait)
            sent.append(time.monotonic())
            sock.sendto(p, ("127.0.0.1", port))
    conn.send(sent)
    conn.close()


def run_block(port: int, probe: Probe, rate: float, first: int
              ) -> tuple[int, int, list[float], list[float]]:
    """Send BLOCK_S seconds of bundles at ``rate`` from another process; returns (sent,
    committed, send-to-bus latencies s, receive-to-bus times s)."""
    import multiprocessing as mp

    ctx = mp.get_context("spawn")
    n = int(BLOCK_S * rate)
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=send_block, args=(port, rate, first, n, child))
    proc.start()
    sent = parent.recv()
    proc.join()
    time.sleep(0.2)
    keys = [first + k for k in range(n) if first + k in probe.on_bus]
    return (n, len(keys), [probe.on_bus[k] - sent[k - first] for k in keys],
            [probe.processing[k] for k in keys])


def parse_costs() -> dict[str, float]:
    from pythonosc.osc_packet import OscPacket

    data = bundle(1, 0.0)
    client = TuioClient()
    fseq = [0]

    def ours() -> None:
        for _ in range(100):
            fseq[0] += 1
            client.apply(decode_packet(data).messages, "127.0.0.1:1", time.monotonic())

    def python_osc() -> None:
        for _ in range(100):
            OscPacket(data)

    t = interleaved({"ours": ours, "python_osc": python_osc}, rounds=30)
    return {"decode_and_apply_us_median": float(np.median(t["ours"])) * 1e4,
            "python_osc_parse_only_us_median": float(np.median(t["python_osc"])) * 1e4,
            "bundle_bytes": len(data)}


def main() -> None:
    check_flags("osc", sys.argv[1:])
    src = OscInput("bench", port=0, table=(1.2, 0.8))
    probe = Probe(src)
    src.on_packet = probe
    loop = Loop(LiveInputs([src], Tracker()), [], [], rate_hz=60.0)
    thread = threading.Thread(target=loop.run, daemon=True)
    thread.start()
    if not src.wait_listening():
        raise SystemExit("bench/osc.py: the osc source did not start listening")
    results = {r: {"sent": 0, "committed": 0, "latency": [], "processing": []} for r in RATES}
    first = 1
    for _ in range(ROUNDS):
        for rate in RATES:  # interleaved blocks: 60 240 60 240 ...
            n, got, lat, proc = run_block(src.bound_port, probe, rate, first)
            first += n + 200  # a forward jump: never late, never a restart
            r = results[rate]
            r["sent"] += n
            r["committed"] += got
            r["latency"] += lat
            r["processing"] += proc
    ticks, fps = loop.stats.ticks, loop.stats.fps() or 0.0
    loop.stop.set()
    thread.join(5.0)
    figures: dict[str, object] = {}
    for rate, r in results.items():
        s = stats_ms(r["latency"]) if r["latency"] else {"median_ms": float("nan"),
                                                         "p99_ms": float("nan")}
        figures[f"hz{rate}"] = {
            "bundles_sent": r["sent"], "bundles_committed": r["committed"],
            "loss_rate": 1.0 - r["committed"] / r["sent"],
            "send_to_bus_median_ms": s["median_ms"], "send_to_bus_p99_ms": s["p99_ms"],
            "send_to_bus_max_ms": float(np.max(r["latency"]) * 1e3) if r["latency"] else None,
            "receive_to_bus_median_ms": float(np.median(r["processing"]) * 1e3),
            "receive_to_bus_p99_ms": float(np.percentile(r["processing"], 99) * 1e3)}
    figures["objects_per_bundle"] = OBJECTS
    figures["loop_ticks"] = ticks
    figures["loop_fps"] = fps
    figures["load_average_1min"] = os.getloadavg()[0]  # other processes share these cores
    figures["bad_input"] = src.bad.counts()
    figures["codec"] = parse_costs()
    budgets = {"loss_rate": 0.0, "send_to_bus_p99_ms": 2.0}
    for rate in RATES:
        f = figures[f"hz{rate}"]
        print(f"{rate:4d} Hz: {f['bundles_committed']}/{f['bundles_sent']} committed, "
              f"send-to-bus median {f['send_to_bus_median_ms']:.3f} ms, "
              f"p99 {f['send_to_bus_p99_ms']:.3f} ms (of which receive-to-bus median "
              f"{f['receive_to_bus_median_ms']:.3f} ms, p99 {f['receive_to_bus_p99_ms']:.3f} ms)")
    emit("osc", figures, budgets)


if __name__ == "__main__":
    main()
