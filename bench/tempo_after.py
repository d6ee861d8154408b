"""A gesture begun where another ended is taken at its own tempo
(:func:`behaviors.mop.tempo.before_attempt`): the progress at which each of the 16 second
gestures of :data:`bench.tempo_span.AFTER` (seeds 0-3, begun where the first ended; the
held-out twenty loaded) is first driven, with the rule and without (``before_attempt`` never
true).

With the rule each is stepped by a group of one (the installation's compiled form, equal to
its follower alone: ``tests/mop/test_tempo.py``), without by the follower alone (the rule is
compiled into the group). Measured: sooner on 13 of 16, later on none, mean 0.136 -> 0.107.
``tests/mop/test_tempo.py`` keeps the two pairs whose second gesture is short (the walk wrist
and the dance ankle, 8 performances).

Printed last: one JSON line (figures ``sooner``, ``later``, ``mean_with``, ``mean_without``);
exits 1 when any is later with the rule, fewer than 8 sooner, or the mean not 0.01 lower.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.common import check_flags  # noqa: E402
from bench.tempo_span import after_performances, compared, judged, with_and_without  # noqa: E402


def main() -> int:
    check_flags("tempo_after", sys.argv[1:], flags=("--cases",))
    from bench.motions import MOCAP_HELD_OUT, gesture_templates, mocap_templates
    from behaviors.mop import tempo
    templates = {**gesture_templates(), **mocap_templates(joints=MOCAP_HELD_OUT)}
    cases = after_performances(templates)

    def rule_off() -> None:
        tempo.before_attempt = lambda samples: False
    now, before = with_and_without(templates, cases, rule_off)
    if "--cases" in sys.argv[1:]:   # per performance: pair, seed, with, without
        for i, (a, b) in enumerate(zip(now, before)):
            print(f"pair {i // 4} seed {i % 4}: {a:.4f} {b:.4f}")
    return judged("tempo_after", compared(now, before), 8, 0.01)


if __name__ == "__main__":
    sys.exit(main())
