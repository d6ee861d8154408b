"""How well the follower tells a designer's take from the action a character knows
(:mod:`tabletop.studio.mop_likeness`): each example gesture re-recorded through the studio
(plainly, and at 0.85x with 0.5 mm of noise) beside each as the face's one known action.
Figures: for the same gesture and for different ones, the range of the share of the take's own
replay followed validly as itself (beside the known action, and alone), of the probability the
known action took, how many were named too like, and the longest :func:`too_like` took.

    python bench/take_likeness.py
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.common import check_flags, emit  # noqa: E402
from tabletop.plugins.mop_table import EXAMPLES, build, designer_config  # noqa: E402
from tabletop.studio.mop_likeness import likeness, too_like  # noqa: E402
from tabletop.studio.mop_table import StudioTable  # noqa: E402

GESTURES = ("circle", "figure_eight", "line", "square", "wave", "zigzag")
TAKES = {"plain": {}, "slow_noisy": {"speed": lambda u: 0.85, "noise": 0.0005}}


def take_of(known: str, gesture: str, how: dict, base: Path):
    cfg = designer_config(base)
    cfg["engines"][0]["characters"][0]["actions"][0].update(
        name=known, template=str(EXAMPLES / f"mop/gestures/{known}.csv"))
    engine = build(cfg, base)
    table = StudioTable(engine, base / "lib")
    table.rest(1.0)
    table.tick(["designer.record"])
    table.perform(gesture, **how)
    table.tick(["designer.record"])
    return engine


def main() -> None:
    check_flags("take_likeness", sys.argv[1:])
    rows: dict[str, list] = {"same": [], "other": []}
    spent = []
    for known in GESTURES:
        for gesture in GESTURES:
            for how in TAKES.values():
                with tempfile.TemporaryDirectory() as d:
                    engine = take_of(known, gesture, how, Path(d))
                    templates, routes, args = engine.follower_plan("hand")
                    t0 = time.perf_counter()
                    like = too_like(engine.make_follower, templates, "take1", **args)
                    spent.append(time.perf_counter() - t0)
                    own, shares = likeness(engine.make_follower, templates, "take1", **args)
                    alone = likeness(engine.make_follower, {"take1": templates["take1"]},
                                     "take1", **args)[0]
                    rows["same" if known == gesture else "other"].append(
                        (own, shares[known], like == known, alone))
    out = {"too_like_ms_max": round(1000 * max(spent), 1)}
    for k, r in rows.items():
        out[f"{k}_own_valid"] = [round(min(x[0] for x in r), 2), round(max(x[0] for x in r), 2)]
        out[f"{k}_known_share"] = [round(min(x[1] for x in r), 2), round(max(x[1] for x in r), 2)]
        out[f"{k}_own_valid_alone"] = [round(min(x[3] for x in r), 2),
                                       round(max(x[3] for x in r), 2)]
        out[f"{k}_named_too_like"] = f"{sum(x[2] for x in r)}/{len(r)}"
    emit("take_likeness", out, {})


if __name__ == "__main__":
    main()
