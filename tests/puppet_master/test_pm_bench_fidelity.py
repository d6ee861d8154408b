"""bench/fidelity.py's per-behaviour list of the misses over several seeds."""

from bench.fidelity import behaviour_misses, engine_misses

KEYS = ("facing", "speed", "still_moving", "orbit")


def _row(*missed: str) -> dict:
    return {f"ok_{k}": k not in missed for k in KEYS}


def test_misses_are_listed_per_behaviour_with_the_engines_own_marked():
    # two seeds of one behaviour: a threshold the designer's own character misses on the same
    # path is listed as missed but not marked as the engine's
    into: dict[str, list[str]] = {}
    seeds = [
        ({"lover": {"slow": _row("still_moving", "orbit"), "fast": _row()}},
         {"lover": {"slow": _row("orbit"), "fast": _row("speed")}}),
        ({"lover": {"slow": _row("still_moving"), "fast": _row("speed")}},
         {"lover": {"slow": _row(), "fast": _row()}}),
    ]
    for seed, (table, reference) in enumerate(seeds):
        behaviour_misses(table, engine_misses(table, reference), seed, into)
    assert sorted(into["lover"]) == sorted(["0:slow:still_moving*", "0:slow:orbit",
                                            "1:slow:still_moving*", "1:fast:speed*"])


def test_the_spread_runs_the_behaviours_again_with_a_perturbed_correction_share():
    # the cloud a change is read against: each run perturbs the drift correction's share of
    # every behaviour and counts the thresholds over the same paths as the unperturbed run
    from bench.fidelity import PERTURBATIONS, cloud
    from behaviors.puppet_master.engine import Params
    from tabletop.examples import DEFAULT_OUT, _trained, designer_table

    behavior, _ = _trained(DEFAULT_OUT, "lover", PERTURBATIONS[0])
    assert behavior.params.relative_motion == Params.relative_motion * (1 + PERTURBATIONS[0])
    seconds = 3.0
    spread = cloud(2, [0], seconds, {0: designer_table(seconds, 0)})
    names = ("lover", "bully", "playful_friend", "stalker", "afraid")
    assert set(spread) == {"thresholds_met", "engine_only_misses",
                           *(f"{n}.{k}" for n in names for k in ("misses",
                                                                 "engine_only_misses"))}
    assert all(len(v) == 2 for v in spread.values())
    for run in range(2):     # 5 behaviours x 3 paths x 8 thresholds
        missed = sum(spread[f"{n}.misses"][run] for n in names)
        assert spread["thresholds_met"][run] == 120 - missed
        assert spread["engine_only_misses"][run] == sum(
            spread[f"{n}.engine_only_misses"][run] for n in names) <= missed
