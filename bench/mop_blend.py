"""The cross-fade of MOP characters (``blend_s``) where the driving action switches.

The MOP paper shows motions as they are, without interpolation; this installation cross-fades
the first ``blend_s`` seconds after the action driving a character changes
(:class:`behaviors.mop.puppetry.Puppet`). Measured here on the example installation
(``examples/mop.yaml``): six back-to-back sequences of four gestures (puck 1 drives the dancer,
puck 2 the salamander, the face and the gecko), at 1x, with no rest between gestures, once with
every character's ``blend_s`` as configured (0.2 s) and once with 0.

Figures per character (metres on the table, 60 Hz frames):
``<blend>_<character>_switch_jump_max_m``, the largest per-frame move of any of its points
within 0.25 s after the driving action changed (from the last action that drove it, including
across the hold between gestures); ``<blend>_<character>_within_jump_p99_m`` and ``_max_m``,
the same over frames within one action after that (the motion's own speed and the follower's
progress steps): the scale a switch is measured against; ``<blend>_<character>_switches``, how
many switches were seen.

    python bench/mop_blend.py
"""

from __future__ import annotations

import copy
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402

#: Each puck's back-to-back sequences (the gestures its characters know).
SEQUENCES = {1: [["circle", "zigzag", "line", "figure_eight"],
                 ["zigzag", "circle", "figure_eight", "line"],
                 ["line", "zigzag", "circle", "zigzag"]],
             2: [["circle", "wave", "line", "zigzag"], ["zigzag", "wave", "circle", "line"],
                 ["square", "figure_eight", "circle", "square"]]}
#: How long after a switch a frame counts as the switch's (s): longer than the cross-fade.
AFTER_S = 0.25


def jumps(frames: list[dict], name: str, rate: float) -> tuple[list[float], list[float], int]:
    """Per-frame largest point moves (metres) of character ``name``: within ``AFTER_S`` of a
    switch of its driving action, and within one action after that; and the switches."""
    after, within, switches = [], [], 0
    prev, last, since = None, None, 10 ** 9
    for c in frames:
        s = c[name]
        if prev is not None and s.valid:
            jump = float(np.max(np.linalg.norm(s.points - prev.points, axis=1)))
            if last is not None and s.action != last:
                switches, since = switches + 1, 0
            if since < int(AFTER_S * rate):
                after.append(jump)
                since += 1
            elif prev.valid:
                within.append(jump)
        prev = s
        if s.valid:
            last = s.action
    return after, within, switches


def measure(blend_s: float | None) -> dict[str, float]:
    """The figures with every character's ``blend_s`` (None: as configured)."""
    from tabletop.config import load_config
    from tabletop.plugins import mop
    from tabletop.plugins.mop_table import EXAMPLES, RATE, Table
    from tabletop.registry import BuildContext
    cfg = copy.deepcopy(load_config(EXAMPLES / "mop.yaml"))
    if blend_s is not None:
        for c in cfg["engines"][0]["characters"]:
            c["blend_s"] = blend_s
    ctx = BuildContext(table=(1.2, 0.8), rate_hz=RATE, config=cfg, base=EXAMPLES)
    after: dict[str, list[float]] = {}
    within: dict[str, list[float]] = {}
    count: dict[str, int] = {}
    for puck, sequences in SEQUENCES.items():
        for seq in sequences:
            table = Table(mop.build(cfg["engines"][0], ctx))
            table.rest(1.0)
            frames = [c for g in seq for _, c in table.perform(g, puck=puck)] + table.rest(1.0)
            for name in frames[0]:
                a, w, n = jumps(frames, name, RATE)
                after.setdefault(name, []).extend(a)
                within.setdefault(name, []).extend(w)
                count[name] = count.get(name, 0) + n
    tag = "configured" if blend_s is None else f"blend_{blend_s:g}"
    out: dict[str, float] = {}
    for name in sorted(within):
        if not count[name]:
            continue
        out[f"{tag}_{name}_switches"] = count[name]
        out[f"{tag}_{name}_switch_jump_max_m"] = max(after[name])
        out[f"{tag}_{name}_within_jump_p99_m"] = float(np.percentile(within[name], 99))
        out[f"{tag}_{name}_within_jump_max_m"] = max(within[name])
    return out


def main() -> None:
    check_flags("mop_blend", sys.argv[1:], [], {})
    figures = {**measure(None), **measure(0.0)}
    for k, v in figures.items():
        print(f"{k:50s} {v:.4g}")
    emit("mop_blend", figures, {})


if __name__ == "__main__":
    main()
