"""More tuning cases of the kinds ``bench/follow_quality.py`` fails on held out: mirrored paths
and gestures back to back among twenty templates, on the tuned joints with other seeds.

For each seed (201-210 unless given): every template mirrored (``bench.motions.unrelated_motions``,
the mirrored ones only) performed at 0.7, 1 and 1.4x with the twenty templates loaded, and eight
back-to-back sequences of four of them (``bench.motions.back_to_back`` drawn with seed + 1000).
Figures: each mirrored performance's valid share (worst, mean, how many over 0.1) and each
sequence's longest run of a wrong action valid (worst, median, how many over 2 samples and their
sum); ``--debug`` prints every mirrored performance over 0.1 and every sequence over 2 with the
action driving. ``--forms=y,xy,r`` measures instead every template drawn in those forms
(``bench.motions.in_form``: mirrored in y, in both, backwards) at 0.7, 1 and 1.4x, the same
figures per form (seeds 201-205 unless given). Tuning cases only: the held-out joints and seed
stay for the final check.

    python bench/follow_widened.py [--seeds=201-210] [--forms=y,xy,r] [--debug]
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from bench.follow_quality import puck_follower, run  # noqa: E402
from bench.follow_sequences import wrong_valid  # noqa: E402
from bench.motions import (MOCAP, back_to_back, drawn_in_form, gesture_templates,  # noqa: E402
                           mocap_templates, performance, unrelated_motions)

DEBUG = "--debug" in sys.argv


def seeds_from(argv: list[str], default: str = "201-210") -> range:
    """``--seeds=A-B`` (inclusive) from ``argv``; ``default`` without it."""
    arg = next((a.split("=", 1)[1] for a in argv if a.startswith("--seeds=")), default)
    try:
        lo, hi = (int(v) for v in arg.split("-"))
    except ValueError:
        raise SystemExit(f"--seeds={arg}: expected two integers as A-B") from None
    return range(lo, hi + 1)


def widened(seeds: range) -> dict[str, float]:
    everything = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    f = puck_follower(everything)
    shares, runs = [], []
    for seed in seeds:
        rng = np.random.default_rng(seed)
        for name, path in unrelated_motions(rng, everything).items():
            if not name.startswith("mirrored_"):
                continue
            for scale in (0.7, 1.0, 1.4):
                states = run(f, performance(rng, path, scale)[0])
                shares.append(float(np.mean([s.valid for s in states])))
                if DEBUG and shares[-1] > 0.1:
                    print(seed, name, scale, round(shares[-1], 3),
                          sorted({s.best for s in states if s.valid}))
        rng = np.random.default_rng(seed + 1000)
        for c in range(8):
            x, truth, prog, order = back_to_back(rng, everything, 4)
            w = wrong_valid(run(f, x), truth, prog, order, everything)
            runs.append(w["longest"])
            if DEBUG and w["longest"] > 2:
                print(seed, c, order, w)
    s, r = np.array(shares), np.array(runs)
    return {"mirrored_20_valid_share_max": float(s.max()),
            "mirrored_20_valid_share_mean": float(s.mean()),
            "mirrored_20_over_10pct": int(np.sum(s > 0.1)),
            "mirrored_20_performances": int(s.size),
            "sequence_20_wrong_valid_longest_ticks_max": int(r.max()),
            "sequence_20_wrong_valid_longest_ticks_median": float(np.median(r)),
            "sequence_20_over_2_ticks": int(np.sum(r > 2)),
            "sequence_20_over_2_ticks_summed": int(r[r > 2].sum()),
            "sequence_20_sequences": int(r.size)}


def in_forms(seeds: range, forms: list[str]) -> dict[str, float]:
    """Each template drawn in each of ``forms`` among the twenty: the valid share's worst, mean
    and how many over 0.1, per form."""
    everything = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    f = puck_follower(everything)
    out: dict[str, float] = {}
    for form in forms:
        shares = []
        for seed in seeds:
            for name, scale, x in drawn_in_form(np.random.default_rng(seed), everything, form):
                states = run(f, x)
                shares.append(float(np.mean([s.valid for s in states])))
                if DEBUG and shares[-1] > 0.1:
                    print(form, seed, name, scale, round(shares[-1], 3),
                          sorted({s.best for s in states if s.valid}))
        s = np.array(shares)
        out |= {f"{form}_20_valid_share_max": float(s.max()),
                f"{form}_20_valid_share_mean": float(s.mean()),
                f"{form}_20_over_10pct": int(np.sum(s > 0.1)), f"{form}_20_performances": s.size}
    return out


def main() -> None:
    check_flags("follow_widened", sys.argv[1:], ["--debug"],
                values={"seeds": "A-B", "forms": "y,xy,r"})
    forms = next((a.split("=", 1)[1].split(",") for a in sys.argv[1:]
                  if a.startswith("--forms=")), None)
    if forms is not None and not set(forms) <= {"x", "y", "xy", "r", "xr", "yr", "xyr"}:
        raise SystemExit(f"--forms={','.join(forms)}: forms are x, y, xy and any with r")
    figures = (in_forms(seeds_from(sys.argv[1:], "201-205"), forms) if forms
               else widened(seeds_from(sys.argv[1:])))
    for k, v in figures.items():
        print(f"{k:50s} {v:.4g}" if isinstance(v, float) else f"{k:50s} {v}")
    emit("follow_widened", figures, {})


if __name__ == "__main__":
    main()
