"""How steadily a Puppet Master behaviour reads its character from a demonstration: each
scripted designer (behaviors/puppet_master/designers.py) records TAKES takes, each on its own
designer_main_path (seeds 5000-5009 and 6000-6019; 40-90 s; 30 / 40 / 50 / 60 Hz), and each
take is trained as a behaviour (Behavior.train, 40 Hz) and its readings counted: a personal
space (personal_space > 0), keeps_pace, walks_with_main, keeps_away, charging (its own
touches of its main beside them). The shipped behaviours
(behaviors/library) are read beside them. A designer who records the same character twice
should get the same character: each reading should go the same way in all of a designer's
takes, and as its shipped behaviour reads (character.py: the figures). Prints a table, then
one JSON line.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python bench/character_reading.py [--seeds 5000,6001]
"""

from __future__ import annotations

import argparse
import functools
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from behaviors.puppet_master import designers  # noqa: E402
from behaviors.puppet_master.behavior import Behavior  # noqa: E402
from tabletop.library import load_behavior  # noqa: E402

TAKE_SEEDS = tuple(range(5000, 5010)) + tuple(range(6000, 6020))
RATES_HZ = (30.0, 40.0, 50.0, 60.0)
READINGS = ("personal_space", "keeps_pace", "walks_with_main", "keeps_away", "charging")


@functools.cache
def _main_path(seed: int, seconds: float, rate_hz: float) -> np.ndarray:
    return designers.designer_main_path(seed, seconds, rate_hz)


def take(personality: str, seed: int) -> np.ndarray:
    """One take (n, 7) of ``personality``'s scripted designer: 40-90 s (drawn from ``seed``)
    at 30 / 40 / 50 / 60 Hz (by ``seed`` mod 4), on the designer's own main path."""
    seconds = float(np.random.default_rng([seed, 77]).uniform(40.0, 90.0))
    rate_hz = RATES_HZ[seed % 4]
    if personality in designers.CHASED:     # its designer's main hand goes after the reactor
        return designers.demonstrate(personality, seed, seconds, rate_hz)
    # the path demonstrate makes by default, made once for the takes of every personality
    # (0.04 CPU s a path; equal to the last digit)
    return designers.demonstrate(personality, seed, seconds, rate_hz,
                                 main=_main_path(seed, seconds, rate_hz).copy())


def reading(b: Behavior) -> dict[str, Any]:
    """A trained behaviour's character: each reading as a bool, and the figures read by."""
    return {"personal_space": b.personal_space > 0.0, "keeps_pace": bool(b.keeps_pace),
            "walks_with_main": bool(b.walks_with_main),
            "keeps_away": bool(b.keeps_away),
            "charging": bool(b.charging),
            "space_m": round(float(b.personal_space), 4),
            "own_touches": int(b.own_touches)}


def study(seeds: tuple[int, ...]) -> dict[str, Any]:
    """Per personality: the shipped behaviour's reading, and per reading how many takes read
    it true / how many read it as the shipped behaviour does."""
    out: dict[str, Any] = {}
    for name in designers.PERSONALITIES:
        stored = load_behavior(ROOT / "behaviors" / "library" / name)
        shipped = reading(Behavior.train(np.asarray(stored.demonstration, dtype=float),
                                         **stored.parameters))
        takes = [reading(Behavior.train(take(name, s))) for s in seeds]
        row: dict[str, Any] = {"shipped": shipped, "takes": len(takes)}
        for r in READINGS:
            row[f"{r}.true"] = sum(t[r] for t in takes)
            row[f"{r}.as_shipped"] = sum(t[r] == shipped[r] for t in takes)
        row["own_touches"] = [t["own_touches"] for t in takes]
        out[name] = row
    out["steady"] = sum(out[n][f"{r}.as_shipped"] for n in designers.PERSONALITIES
                        for r in READINGS)
    out["readings"] = len(designers.PERSONALITIES) * len(READINGS) * len(seeds)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default=None,
                    help="comma-separated take seeds (default 5000-5009, 6000-6019)")
    a = ap.parse_args(argv)
    try:
        seeds = TAKE_SEEDS if a.seeds is None else tuple(int(s) for s in a.seeds.split(","))
    except ValueError:
        ap.error(f"--seeds: expected comma-separated integers, got {a.seeds!r}")
    res = study(seeds)
    print(f"{'designer':16s}" + "".join(f"{r:>18s}" for r in READINGS) + "  (takes read true,"
          " as shipped / takes; shipped reading)")
    for name in designers.PERSONALITIES:
        row = res[name]
        cells = "".join(f"{row[f'{r}.true']:>5d} {row[f'{r}.as_shipped']:>3d}/{row['takes']:<3d}"
                        f"{'T' if row['shipped'][r] else 'F':>5s}" for r in READINGS)
        print(f"{name:16s}{cells}")
    print(f"readings as shipped: {res['steady']} of {res['readings']}")
    print(json.dumps(res, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
