"""A gesture's tempo asked over its own samples (:func:`behaviors.mop.tempo.span`): the progress
at which each of 32 gestures of the held-out twenty is first driven, with the rule and without
(the demand over the whole window: ``tempo.span`` constant).

The gestures: the second of each pair of :data:`AFTER` (the held-out twenty's gestures held by
the tempo past their observer's reach in ``bench/follow_seeds.py``'s sequences) begun where the
first ended, and the same from rest, seeds 0-3 each (0.8-1.2x, time-warped, the bench's
jitter); the twenty loaded. With the rule each is stepped by a group of one (the installation's
compiled form, equal to its follower alone: ``tests/mop/test_group.py``), without by the
follower alone (the rule compiled into the group). Measured: sooner on 7 of 32 (the walk wrist
and dance ankle, short templates), later on none, mean 0.128 -> 0.123.
``tests/mop/test_tempo.py`` keeps the walk wrist and the dance ankle.

Printed last: one JSON line (figures ``sooner``, ``later``, ``mean_with``, ``mean_without``);
exits 1 when any is later with the rule, fewer than 5 sooner, or the mean not 0.004 lower.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Callable

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402

#: gestures of the held-out twenty that followed another one and were held by the tempo past
#: their observer's reach + 0.05 in bench/follow_seeds.py's sequences (seeds 101-106), each after
#: the gesture that ended before it there
AFTER = (("line", "spinkick_right_wrist"), ("dance_a_right_ankle", "walk_left_wrist"),
         ("backflip_left_ankle", "roll_right_wrist"), ("jump_left_ankle", "dance_a_right_ankle"))


def after_performances(templates, pairs=AFTER) -> list[tuple[np.ndarray, str, np.ndarray, int]]:
    """Per pair of ``pairs`` and seed 0-3: the second gesture begun where the first ended (no
    rest, 0.8-1.2x, time-warped, the bench's jitter): samples, its name, its true progress and
    the sample it begins at."""
    from bench.motions import JITTER_M, at_phase, phase_of
    out = []
    for first, second in pairs:
        for seed in range(4):
            rng = np.random.default_rng(seed)
            parts, at = [], np.zeros(2)
            for g in (first, second):
                phase, p = phase_of(rng, len(templates[g]))
                parts.append(float(rng.uniform(0.8, 1.2)) * at_phase(templates[g], phase) + at)
                at = parts[-1][-1].copy()
            x = np.concatenate([np.zeros((15, 2))] + parts + [np.zeros((15, 2)) + at])
            x += rng.normal(0, JITTER_M, x.shape)
            out.append((x, second, p[:, 0], 15 + len(parts[0])))
    return out


def from_rest_performances(templates, names=None) -> list[tuple[np.ndarray, str, np.ndarray,
                                                                 int]]:
    """The second gestures of :data:`AFTER` (or ``names``) from rest, seeds 0-3 (0.8-1.2x,
    time-warped, the bench's jitter): samples, its name, its true progress and the sample it
    begins at."""
    from bench.motions import JITTER_M, at_phase, phase_of
    out = []
    for name in names or dict.fromkeys(second for _, second in AFTER):
        for seed in range(4):
            rng = np.random.default_rng(seed)
            phase, p = phase_of(rng, len(templates[name]))
            part = float(rng.uniform(0.8, 1.2)) * at_phase(templates[name], phase)
            x = np.concatenate([np.zeros((15, 2)), part, np.zeros((15, 2)) + part[-1]])
            x += rng.normal(0, JITTER_M, x.shape)
            out.append((x, name, p[:, 0], 15))
    return out


def recognised(states: list, name: str, prog: np.ndarray, begin: int) -> float:
    """The progress at which ``name`` (true progress ``prog`` from sample ``begin``) is first
    driven, 1 when never."""
    hit = [p for s, p in zip(states[begin:], prog) if s.valid and s.best == name]
    return float(hit[0]) if hit else 1.0


def with_and_without(templates: dict, cases: list, rule_off: Callable[[], None]
                     ) -> tuple[np.ndarray, np.ndarray]:
    """The progress at which each case is first driven with a rule (stepped by a group of one,
    the installation's compiled form, equal to its follower alone) and without it (``rule_off``
    switches the Python follower's rule off; the follower stepped alone)."""
    from bench.follow_quality import puck_follower, run
    from behaviors.mop.group import FollowerGroup
    group = FollowerGroup([puck_follower(templates)])
    now = []
    for x, name, prog, begin in cases:
        group.reset()
        now.append(recognised([group.step([s])[0] for s in x], name, prog, begin))
    rule_off()
    f = puck_follower(templates)
    before = np.array([recognised(run(f, x), name, prog, begin)
                       for x, name, prog, begin in cases])
    return np.array(now), before


def compared(now: np.ndarray, before: np.ndarray) -> dict[str, float]:
    """Counts of cases driven sooner and later with the rule, and both means (progress)."""
    return {"performances": len(now), "sooner": int(np.sum(now < before - 1e-9)),
            "later": int(np.sum(now > before + 1e-9)), "mean_with": float(now.mean()),
            "mean_without": float(before.mean())}


def judged(name: str, out: dict[str, float], sooner_least: int, lower_by: float) -> int:
    """Prints ``out`` as the bench's JSON line; 0 when no case is later with the rule, at least
    ``sooner_least`` sooner and the mean ``lower_by`` (progress) lower, else 1."""
    emit(name, out, {"later": 0, "sooner_least": sooner_least, "mean_lower_by": lower_by})
    ok = (out["later"] == 0 and out["sooner"] >= sooner_least
          and out["mean_with"] <= out["mean_without"] - lower_by)
    return 0 if ok else 1


def main() -> int:
    check_flags("tempo_span", sys.argv[1:])
    from bench.motions import MOCAP_HELD_OUT, gesture_templates, mocap_templates
    from behaviors.mop import tempo
    templates = {**gesture_templates(), **mocap_templates(joints=MOCAP_HELD_OUT)}
    cases = from_rest_performances(templates) + after_performances(templates)

    def rule_off() -> None:
        tempo.span = lambda samples: float(tempo.TEMPO_SAMPLES)
    return judged("tempo_span", compared(*with_and_without(templates, cases, rule_off)), 5, 0.004)


if __name__ == "__main__":
    sys.exit(main())
