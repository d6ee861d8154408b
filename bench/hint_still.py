"""Early feedback never shown on a still input (:class:`behaviors.mop.hints.HintGate`), on the
example installation (``examples/mop.yaml``, 60 Hz, the tracker's 0.7 mm jitter): 8 draws
(seeds 0-7) of puck 1 resting 2 s, lifted 1 s and put down elsewhere, still for 3 s, and 6
draws (seeds 0-5) of the right hand's finger put down after 1 s and held still 3 s.

Measured: no draw hinted. Were a lift counted as a rest (the gate kept calm while the input
is missing), 7 of the 8 puck draws would be hinted (4-12 frames, 0.03-0.45 s after the puck
is put down; none on seed 4) and one of the 6 finger draws (seed 3: 12 frames).
``tests/mop/test_hints.py`` keeps the puck's seeds 0-2 and the finger's seeds 3 and 5.

Printed last: one JSON line (figures ``puck_draws``, ``puck_hinted``, ``finger_draws``,
``finger_hinted``: draws with any frame hinted); exits 1 when any draw is hinted.
"""

from __future__ import annotations

import copy
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402

JITTER_M = 0.0007   # the tracker's, standard deviation per axis


def validated_table(cfg: dict):
    """A 60 Hz table driving the MOP engine of ``cfg`` (a validated config: its first
    engine), files relative to the examples."""
    from tabletop.plugins import mop
    from tabletop.plugins.mop_table import EXAMPLES, RATE, Table
    from tabletop.registry import BuildContext
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=cfg, base=EXAMPLES)
    return Table(mop.build(cfg["engines"][0], ctx))


def jittered_rest(table, seconds: float, rng: np.random.Generator, puck: int = 1) -> list:
    """``seconds`` of frames with ``puck`` still where it stands, jittered; the characters of
    each frame."""
    from tabletop.plugins.mop_table import RATE
    x0, y0 = table.pucks[puck]
    out = []
    for _ in range(int(seconds * RATE)):
        table.pucks[puck] = (x0 + rng.normal(0, JITTER_M), y0 + rng.normal(0, JITTER_M))
        out.append(table.tick())
    table.pucks[puck] = (x0, y0)
    return out


def lifted_puck(cfg: dict, seed: int) -> float:
    """The highest hint level of the dancer and the bird while puck 1 of draw ``seed`` is lifted
    and put down still (after a 2 s rest, lifted 1 s, then 3 s still)."""
    from tabletop.drawing.life import hint_level
    from tabletop.plugins.mop_table import RATE
    rng = np.random.default_rng(seed)
    table = validated_table(cfg)
    jittered_rest(table, 2.0, rng)
    table.pucks.pop(1)
    lifted = [table.tick() for _ in range(int(RATE))]
    table.pucks[1] = (0.5, 0.35)
    down = jittered_rest(table, 3.0, rng)
    return max(hint_level(ch[c]) for ch in lifted + down for c in ("dancer", "bird"))


def touch_config(cfg: dict) -> dict:
    """``cfg`` with the right hand performing by touch."""
    cfg = copy.deepcopy(cfg)
    for p in cfg["engines"][0]["performers"]:
        if p["name"] == "right_hand":
            p["inputs"] = [{"kind": "touch"}]
    return cfg


def still_finger(cfg: dict, seed: int):
    """The highest hint level of every character at each frame of draw ``seed``'s finger put
    down after 1 s and held still 3 s (``cfg``: :func:`touch_config`'s); the table and its
    generator (a gesture may follow)."""
    from tabletop.drawing.life import hint_level
    from tabletop.frames import Touch
    rng = np.random.default_rng(seed)
    table = validated_table(cfg)
    for _ in range(60):
        table.tick()
    still = []
    for _ in range(180):
        table.touches = (Touch(1, 0.6 + rng.normal(0, JITTER_M), 0.4 + rng.normal(0, JITTER_M)),)
        still.append(max(hint_level(c) for c in table.tick().values()))
    return still, table, rng


def main() -> int:
    check_flags("hint_still", sys.argv[1:])
    from tabletop.config import load_config
    from tabletop.plugins.mop_table import EXAMPLES
    cfg = load_config(EXAMPLES / "mop.yaml")
    puck = [lifted_puck(cfg, seed) for seed in range(8)]
    finger = [max(still_finger(touch_config(cfg), seed)[0]) for seed in range(6)]
    out = {"puck_draws": len(puck), "puck_hinted": sum(h > 0 for h in puck),
           "finger_draws": len(finger), "finger_hinted": sum(h > 0 for h in finger)}
    emit("hint_still", out, {"puck_hinted": 0, "finger_hinted": 0})
    return 0 if out["puck_hinted"] == 0 and out["finger_hinted"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
