"""``bench/follow_quality.py``'s held-out evaluation over several seeds: how much one seed flatters.

The held-out evaluation (fourteen other joints of the clips, ``MOCAP_HELD_OUT``, never tuned on)
draws its performances from one seed (``follow_quality.HELD_OUT_SEED``); another seed draws
other sizes, tempi, pauses and jitter. This runs that same evaluation
(:func:`bench.follow_quality.evaluate`) once per seed and prints, per seed, the figures the
issue targets (``follow_quality.TARGETS``, those of the sections measured) and those printed
beside them (``follow_quality.BESIDE``, no target: the longest wrong run back to back however
indistinguishable, and the share of wrong ticks no observer could yet tell, beside the target
``..._wrong_valid_avoidable_longest_ticks_max``, the runs a follower could avoid, at most 2
ticks), then one JSON line:
``heldout_<figure>_seed<N>`` per seed, ``heldout_<figure>_worst`` (the lowest where the target
is a floor, the highest where it is a ceiling) and ``heldout_<figure>_mean`` over the seeds, and
``targets_missed``: the worst figures that miss their targets.

    python bench/follow_seeds.py [--seeds=101,102,...]
        [--sections=sized,holds,sequences,unrelated,after,pauses,shapes]
        [--follower=puck|cli_default|cli_scale]

``--seeds`` (whole numbers, default 101-106); ``--sections`` as ``follow_quality``'s (a section
left out still draws its random numbers, so each seed's figures are those of a full run);
``--follower``: the follower as a puck's path is followed live (``puck``, the default) or as the
``follow`` command builds it by default (``cli_default``) or with ``--invariance scale``
(``cli_scale``).
Deterministic; all sections on six seeds take about 160 s of CPU (66 s with
``--sections=unrelated,sized,holds``).
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from bench import follow_quality as fq  # noqa: E402
from bench.common import check_flags, emit  # noqa: E402
from bench.motions import MOCAP_HELD_OUT  # noqa: E402

#: The held-out seeds measured by default: the single one of follow_quality and five more.
SEEDS = tuple(range(fq.HELD_OUT_SEED, fq.HELD_OUT_SEED + 6))


def parse(args: list[str]) -> tuple[tuple[int, ...], set[str] | None, str]:
    """The seeds, the sections (None: all) and the follower's name of the command line; a wrong
    one exits with one line naming it (:func:`bench.common.check_flags`, each seed as a number in
    its range)."""
    seeds = next((a.split("=", 1)[1].split(",") for a in args if a.startswith("--seeds=")), None)
    # each seed checked as one number: --seeds=1,x is refused as --seeds=x would be
    split = [a for a in args if not a.startswith("--seeds=")] + [
        f"--seeds={s}" for s in seeds or ()]
    check_flags("follow_seeds", split, [], {"sections": fq.SECTION_NAMES,
                                             "follower": tuple(fq.FOLLOWERS)},
                {"seeds": (0, 999999)})
    follower = next((a.split("=", 1)[1] for a in args if a.startswith("--follower=")), "puck")
    if "," in follower:
        sys.exit(f"follow_seeds: --follower: expected one name, got {follower!r}")
    bad = next((s for s in seeds or () if not float(s).is_integer()), None)
    if bad is not None:
        sys.exit(f"follow_seeds: --seeds: expected whole numbers, got {bad!r}")
    sections = next((set(a.split("=", 1)[1].split(",")) for a in args
                     if a.startswith("--sections=")), None)
    return (SEEDS if seeds is None else tuple(int(float(s)) for s in seeds)), sections, follower


def worst(key: str, values: list[float]) -> float:
    """The worst of one targeted figure over the seeds: the lowest for a floor (``>=``), else
    (a ceiling or a figure printed beside the targets, ``follow_quality.BESIDE``) the highest."""
    return min(values) if fq.TARGETS.get(key, ("<=",))[0] == ">=" else max(values)


def summary(per_seed: dict[int, dict[str, float]]) -> tuple[dict[str, float | str],
                                                            dict[str, str]]:
    """(figures, budgets) of the JSON line from each seed's held-out figures (``evaluate``'s
    names): each targeted figure per seed, its worst and mean, and the targets the worst miss."""
    figures: dict[str, float | str] = {"seeds": ",".join(str(s) for s in per_seed)}
    budgets: dict[str, str] = {}
    missed = []
    for key in (*fq.TARGETS, *fq.BESIDE):
        values = [fig[key] for fig in per_seed.values() if key in fig]
        if not values:
            continue
        for seed, fig in per_seed.items():
            figures[f"heldout_{key}_seed{seed}"] = fig[key]
        w = worst(key, values)
        figures[f"heldout_{key}_worst"] = w
        figures[f"heldout_{key}_mean"] = float(np.mean(values))
        if key not in fq.TARGETS:   # printed beside the targets, none itself
            continue
        op, limit = fq.TARGETS[key]
        budgets[f"heldout_{key}_worst"] = f"{op} {limit:g}"
        if not (w >= limit if op == ">=" else w <= limit):
            missed.append(f"heldout_{key}_worst")
    figures["targets_missed"] = " ".join(sorted(missed))
    return figures, budgets


def main() -> None:
    seeds, fq.SECTIONS, follower = parse(sys.argv[1:])
    per_seed = {s: fq.evaluate(fq.FOLLOWERS[follower], s, MOCAP_HELD_OUT) for s in seeds}
    keys = [k for k in (*fq.TARGETS, *fq.BESIDE) if any(k in fig for fig in per_seed.values())]
    width = max(len(k) for k in keys + ["held-out figure"]) + 1
    print(f"{'held-out figure':{width}s}" + "".join(f"{s:>10d}" for s in seeds)
          + f"{'worst':>10s}{'mean':>10s}  target")
    for key in keys:
        values = [per_seed[s][key] for s in seeds]
        print(f"{key:{width}s}" + "".join(f"{v:10.4g}" for v in values)
              + f"{worst(key, values):10.4g}{np.mean(values):10.4g}  "
              + " ".join(map(str, fq.TARGETS.get(key, ("(beside)",)))))
    figures, budgets = summary(per_seed)
    emit("follow_seeds", {"follower": follower, **figures}, budgets)


if __name__ == "__main__":
    main()
