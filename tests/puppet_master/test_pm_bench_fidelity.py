"""bench/fidelity.py's per-behaviour summary of the misses over several seeds."""

from bench.fidelity import engine_misses, tally

KEYS = ("facing", "speed", "still_moving", "orbit")


def _row(*missed: str) -> dict:
    return {f"ok_{k}": k not in missed for k in KEYS}


def test_misses_are_summed_per_behaviour_with_the_engines_own():
    # two seeds of one behaviour: a threshold the designer's own character misses on the same
    # path is counted as missed but not as the engine's
    summary: dict[str, dict[str, list[int]]] = {}
    seeds = [
        ({"lover": {"slow": _row("still_moving", "orbit"), "fast": _row()}},
         {"lover": {"slow": _row("orbit"), "fast": _row("speed")}}),
        ({"lover": {"slow": _row("still_moving"), "fast": _row("speed")}},
         {"lover": {"slow": _row(), "fast": _row()}}),
    ]
    for table, reference in seeds:
        tally(summary, table, engine_misses(table, reference))
    assert summary == {"lover": {"still_moving": [2, 2], "orbit": [1, 0], "speed": [1, 1]}}
