"""Kiosk recovery benchmark: how long the supervisor takes to have the table back.

Each round runs the supervisor on a small installation (scripted pucks, one reactor, headless
view) with the drill engine crashing it (SIGABRT in an engine) on its first start and freezing
its frame loop on its second: measured from the crash (the child's death) or the stall's
detection (no frame for ``stall_s`` = 1 s) to the new installation's READY. Compared: with the
warm spare (a next process already started and waiting, imports done) and without, interleaved
A B A B. Budget (issue 15): back within 2 s.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import yaml  # noqa: E402

from bench.common import emit  # noqa: E402
from tabletop.kiosk.supervisor import Policy, Supervisor  # noqa: E402

ROUNDS = 4


def one_round(spare: bool) -> tuple[float, float]:
    with tempfile.TemporaryDirectory() as d:
        cfg = Path(d) / "config.yaml"
        cfg.write_text(yaml.safe_dump({
            "loop": {"rate_hz": 30},
            "sources": [{"kind": "scripted", "pucks": [1, 2]}],
            "engines": [{"kind": "puppet_master", "name": "lover", "main": {"puck": 1},
                         "behavior": str(ROOT / "behaviors" / "library" / "lover")},
                        {"kind": "fault", "name": "drill", "faults": [
                            {"start": 0, "after_s": 2.0, "kind": "crash"},
                            {"start": 1, "after_s": 2.0, "kind": "stall"}]}],
            "view": {"size": [320, 180], "headless": True},
            "kiosk": {"heartbeat": {"enabled": False}},
        }))
        sup = Supervisor([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                          "--kiosk", "--headless"],
                         Policy(stall_s=1.0, backoff_s=(0.1, 2.0)), Path(d) / "crashes.log",
                         echo=False, spare=spare)
        import threading
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
    return ev[2][1] - ev[1][1], ev[4][1] - ev[3][1]


def main() -> None:
    got: dict[str, list[tuple[float, float]]] = {"spare": [], "no_spare": []}
    for _ in range(ROUNDS):
        for name in got:
            got[name].append(one_round(name == "spare"))
    figures = {}
    for name, rows in got.items():
        crash = [r[0] for r in rows]
        stall = [r[1] for r in rows]
        figures[f"{name}_crash_to_ready_s_median"] = round(statistics.median(crash), 3)
        figures[f"{name}_crash_to_ready_s_max"] = round(max(crash), 3)
        figures[f"{name}_stall_detected_to_ready_s_median"] = round(statistics.median(stall), 3)
        figures[f"{name}_stall_detected_to_ready_s_max"] = round(max(stall), 3)
    figures["rounds"] = ROUNDS
    figures["backoff_s"] = [0.1, 2.0]
    figures["stall_s"] = 1.0
    emit("kiosk", figures, {"spare_crash_to_ready_s_max": 2.0,
                            "spare_stall_detected_to_ready_s_max": 2.0})


if __name__ == "__main__":
    main()
