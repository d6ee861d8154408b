"""Soak benchmark: one hour of table time on a simulated clock, everything on.

The installation of :func:`tabletop.kiosk.simulate.soak_config` (synthetic camera rendering and
detecting every frame, Puppet Master and MOP engines, studio with a take recorded, trained and
discarded every two minutes, kiosk attract mode, status file and heartbeat, the headless view)
runs 3,600 simulated seconds at 2 ticks per simulated second. Reported: resident memory every
five simulated minutes, its growth after a ten-minute warm-up (budget < 10 MB), and the wall
milliseconds per tick in the first and last five minutes (the rate staying steady: budget last
<= 1.25 x first; also in process CPU time, which a shared machine disturbs less, from the
end of the warm-up), and the live Python objects (growth after the warm-up: budget < 500).
The machine is shared: wall figures carry its load.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import yaml  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from tabletop.kiosk.simulate import soak, soak_config  # noqa: E402

RATE = 2.0


def main() -> None:
    check_flags("soak", sys.argv[1:])
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "config.yaml"
        path.write_text(yaml.safe_dump(soak_config(ROOT, RATE)))
        r = soak(path, seconds=3600, rate_hz=RATE, warmup_s=600, every_s=300,
                 studio_keys_every_s=120)
    growth_mb = (r["rss_end_bytes"] - r["rss_start_bytes"]) / 1e6
    first, last = r["wall_s_per_1000_ticks_first"], r["wall_s_per_1000_ticks_last"]
    emit("soak", {
        "simulated_s": 3600, "ticks": r["ticks"], "studio_tries": r["tries"],
        "errors": r["errors"], "rss_growth_mb": round(growth_mb, 2),
        "rss_mb_every_5_min": [round(x / 1e6, 1) for x in r["rss_samples"]],
        "wall_ms_per_tick_first_5_min": round(first, 2),
        "wall_ms_per_tick_last_5_min": round(last, 2),
        "rate_ratio_last_to_first": round(last / first, 3),
        "cpu_ms_per_tick_every_5_min": [round(x, 2) for x in r["cpu_s_per_1000_ticks"]],
        "cpu_ratio_last_to_first_after_warmup": round(
            r["cpu_s_per_1000_ticks"][-1] / r["cpu_s_per_1000_ticks"][2], 3),
        "objects_growth": r["objects_end"] - r["objects_start"],
        "objects_every_5_min": r["objects_samples"],
    }, {"rss_growth_mb": 10.0, "rate_ratio_last_to_first": 1.25,
        "cpu_ratio_last_to_first_after_warmup": 1.25, "objects_growth": 500, "errors": 0})


if __name__ == "__main__":
    main()
