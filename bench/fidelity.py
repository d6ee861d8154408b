"""Puppet Master fidelity: every shipped behaviour on main paths it never saw, against its own
demonstration (behaviors/puppet_master/fidelity.py defines the figures and thresholds).

For each behaviour in behaviors/library and each unseen main path (a slow wanderer with pauses
at 30 Hz, a fast reversing hand at 60 Hz, loops and spins in place at 45 Hz; 40 s each), the
reactor is generated causally as it would be live and measured beside its demonstration:
distance-to-main W1, sector occupancy, speeds (all, main still, main moving), facing-the-main
share, per-step look change, turn-limiter saturation, direction-change texture, contact share
and orbit rate. Prints a table per behaviour, then one JSON line.

    .venv/bin/python bench/fidelity.py [--seconds 40] [--seed 0]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.common import emit  # noqa: E402
from tabletop.examples import fidelity_table, print_fidelity  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    t0 = time.perf_counter()
    table = fidelity_table(seconds=args.seconds, seed=args.seed)
    print_fidelity(table)
    figures: dict[str, object] = {}
    passed = total = 0
    per_threshold: dict[str, int] = {}
    for name, paths in table.items():
        for path, row in paths.items():
            total += 1
            passed += int(row["ok"])
            for k, v in row.items():
                figures[f"{name}.{path}.{k}"] = v
                if k.startswith("ok_"):
                    per_threshold[k[3:]] = per_threshold.get(k[3:], 0) + int(v)
    figures["pairs_within_every_threshold"] = passed
    figures["pairs_total"] = total
    for k, v in per_threshold.items():
        figures[f"pairs_within_{k}"] = v
    figures["thresholds_met"] = sum(per_threshold.values())
    figures["thresholds_total"] = total * len(per_threshold)
    figures["seconds_per_path"] = args.seconds
    figures["run_s"] = time.perf_counter() - t0
    budgets = {"facing_abs_diff": 0.1, "look_change_ratio": [0.67, 1.5],
               "texture_ratio": [0.67, 1.5], "speed_w1_share_of_mean_demo_speed": 0.2,
               "events_share": 0.3, "saturation_over_demo": 0.1}
    emit("fidelity", figures, budgets)


if __name__ == "__main__":
    main()
