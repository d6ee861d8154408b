"""How early any follower could tell each example gesture from the others (an ideal observer).

For each of the six example gestures (``examples/mop/gestures``) and each progress p (steps of
1%): its path from its start up to p, noise-free, is compared with every open-ended start of
every other gesture's path at any size 0.46-2.25x (the follower's size range 0.55-1.8 over the
0.8-1.2x sizes ``bench/follow_quality.py`` draws) and any tempo (both paths resampled by arc
length): the gesture can be told apart at p when every other path strays from it by more than
``theta`` somewhere. Paths within ``theta`` of each other cannot be told apart under a few
millimetres of tracking jitter and model error, whatever the follower. Printed: that earliest
progress per gesture at theta 2 and 4 mm, and the share of the six that can be told apart
before 20% of them (``follow_quality``'s back-to-back target: each gesture recognised within
20%). Beside each gesture: its median recognition progress by the follower in back-to-back
sequences (``bench/follow_quality.py``'s draws for options, seed ``OPTION_SEED``, 16 sequences of
four), how far that lies behind the reach, and the share of gestures recognised within 20% or,
where no observer could tell them apart so early, by their reach at 2 mm.

How long each gesture's start is also the start of an unrelated motion (:func:`told_from_unrelated`,
``{gesture}_told_from_{motion}_progress_theta_2mm``): the figure eight's of the diagonal line until
0.21 of it, the circle's of the triangle's first stroke until 0.18, the zigzag's 0.08 and the
wave's 0.12 of any: recognised within 20%, the figure eight and the circle would drive those
motions' starts too, which the follower refuses (:mod:`behaviors.mop.spotting`, "What is out of
reach").

What holds each gesture back (:func:`gates`): in the same sequences, for each rule an action must
pass before it drives (:data:`GATES`), the progress of the gesture from which that rule held for
the true template without a break until the gesture was recognised; per gesture the median, and
the rules whose median is latest (printed as ``{gesture}_last_gate``, joined by ``+`` where
several clear at the same sample; ``--debug`` prints every gesture performed).

Which wrong runs any follower could have avoided (``follow_quality.sequences`` among the six
gestures and among all twenty, with :func:`indistinguishable`): in the same sequences, each
tick where a wrong action drives (``valid`` with ``best`` not the gesture performed) is
*indistinguishable* when
the gesture's path so far (noise-free) is still within 2 mm of a start of the driving action's
path at some size and tempo (:func:`closest_start`), or has not yet left its own start by
2 mm (the ended gesture's rest and the next one's eased start look the same). Printed: the
share of wrong ticks indistinguishable, and the longest run of wrong ticks an observer could
already have told (``wrong_valid_avoidable_longest_ticks_max``; the issue's target for
back-to-back gestures, "no wrong action valid for more than 2 ticks", is on it: what a follower
could avoid; the longest run of every wrong tick is printed beside it). Deterministic; not timed.

Which wrong runs any follower could avoid (``bench/follow_quality.py --sections=sequences``,
``..._wrong_valid_indistinguishable_share`` and ``..._avoidable_longest_ticks_max``, by
``bench/spotting_reach.indistinguishable``): of the ticks where a wrong action drives among the
six gestures back to back, 0.86 (held-out 0.64) fall where the gesture's path so far is still,
within 2 mm, a start of the driving action's path at some size and tempo, or has not yet left
its own start; the longest run an observer could already have told is 2 ticks (held-out 5: the
circle on a square's second side, just after its corner). The longest wrong runs (10 / 7, the
line on the square's first side, before shared starts were on) end within 2 ticks of the
corner, where the two part: no follower tells them apart sooner. Among all twenty (held-out
seeds 101-112, ``bench/follow_seeds.py --sections=sequences``): 0.62-1.0 of the wrong ticks
indistinguishable per seed; the runs of 3-4 (101, 106, 107, 109) are the ended action still
driving while the next gesture has moved 0.0-1.3 mm from its start (0.000-0.066 of it), or the
line on the square's first side (106, 1.7-1.9 mm); the avoidable longest 0-2 (108's 3, the spin
wrist on a circle drawn 1.2x at 0.31-0.34 of it, is 2 since
:data:`behaviors.mop.speed_profile.QUICK_AHEAD`). The observer costs 0.05 CPU s of the 40 s a
six-seed sequences run takes (its answers kept per template set).

How near that run was: the circle at 0.31 / 0.33 / 0.34 of it lies 3.21 / 4.05 / 3.31 mm from
every start of the spin's wrist path on :func:`closest_start`'s grid (40 sizes, 15 lengths),
2.25-2.48 mm on a fine one (400 sizes, 300 lengths, 24 or 60 points): avoidable either way by
the definition here (both paths resampled by arc length, compared point by point). Matched at
any timing of the two instead (the discrete Frechet distance, 60 points against 600 of the
spin's, 120 sizes) it lies 1.21 / 1.23 / 1.51 mm from one (the spin at 1.05-1.07x, up to
0.23-0.25 of its path): a pointwise match by arc length is one timing of many, so this observer
tells paths apart sooner than one matching them at any timing would.

    python bench/spotting_reach.py [--debug]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from bench.common import check_flags, emit  # noqa: E402
from behaviors.mop import shape_lead  # noqa: E402
from behaviors.mop.follower import ActionFollower  # noqa: E402
from bench.follow_quality import DEBUG, OPTION_SEED, puck_follower, run  # noqa: E402
from bench.follow_sequences import sequences  # noqa: E402
from bench.motions import (at_phase, back_to_back, gesture_templates,  # noqa: E402
                           unrelated_motions)

POINTS = 24
SIZES = np.geomspace(0.46, 2.25, 40)


def by_arc(path: np.ndarray, m: int = POINTS) -> tuple[np.ndarray, float]:
    """``m`` points evenly spaced along ``path`` (metres), and its length."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    if s[-1] < 1e-12:
        return np.repeat(path[:1], m, 0), 0.0
    u = np.linspace(0.0, s[-1], m)
    return np.stack([np.interp(u, s, path[:, j]) for j in range(path.shape[1])], 1), float(s[-1])


def closest_start(prefix: np.ndarray, other: np.ndarray) -> float:
    """Smallest largest distance (metres) between ``prefix`` and a start of ``other`` (any
    size in :data:`SIZES`, any length within half to twice the prefix's)."""
    if np.max(np.linalg.norm(prefix - prefix[0], axis=1)) <= 1e-9:
        return 0.0
    ra, la = by_arc(prefix)
    fine = at_phase(other, np.linspace(0, len(other) - 1, 600))
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(fine, axis=0), axis=1))])
    # by size (rows) and length: the start of ``fine`` that long, as its last point's index
    ends = np.searchsorted(cum, la * np.geomspace(0.5, 2.0, 15)[None, :] / SIZES[:, None])
    reached = ends < len(fine)
    if not reached.any():
        return np.inf
    ends = np.maximum(1, ends[reached])
    # a start at size s is the start's points by arc (:func:`by_arc`) times s (its arc length
    # is s times as long): each start resampled once, then scaled to every size reaching its end
    uniq, which = np.unique(ends, return_inverse=True)
    along = np.linspace(0.0, 1.0, POINTS)[None, :] * cum[uniq][:, None]
    starts = np.stack([np.interp(along, cum, fine[:, k]) for k in range(fine.shape[1])], 2)
    starts[cum[uniq] < 1e-12] = fine[0]
    sizes = np.broadcast_to(SIZES[:, None], reached.shape)[reached]
    gaps = np.linalg.norm(ra[None] - sizes[:, None, None] * starts[which], axis=2)
    return float(gaps.max(axis=1).min())


def earliest(name: str, templates: dict[str, np.ndarray], theta: float) -> float:
    """The earliest progress (0..1) at which gesture ``name`` strays from every other start by
    more than ``theta`` metres (1 when never)."""
    tpl = templates[name]
    for p in np.arange(0.02, 1.0001, 0.01):
        prefix = at_phase(tpl, np.linspace(0, p * (len(tpl) - 1), int(400 * p) + 2))
        if np.max(np.linalg.norm(prefix - prefix[0], axis=1)) <= theta:
            continue   # not yet away from its start by theta: the start of anything
        if all(closest_start(prefix, b) > theta for other, b in templates.items() if other != name):
            return round(float(p), 2)
    return 1.0


def straight_until(path: np.ndarray, theta: float) -> float:
    """The earliest progress (0..1, steps of 1%) at which ``path`` (metres) so far strays from
    its chord (its start to there) by more than ``theta`` metres: before it the path is a
    straight stroke, any straight stroke in its direction as much its start (1 when never)."""
    for p in np.arange(0.02, 1.0001, 0.01):
        prefix = at_phase(path, np.linspace(0, p * (len(path) - 1), int(400 * p) + 2))
        r = prefix - prefix[0]
        chord = float(np.linalg.norm(r[-1]))
        if chord <= 1e-12:
            continue
        u = r[-1] / chord
        off = r - np.outer(r @ u, u)
        if float(np.max(np.linalg.norm(off, axis=1))) > theta:
            return round(float(p), 2)
    return 1.0


#: The unrelated motions (``bench/motions.unrelated_motions``) a gesture's start is compared with
#: in :func:`told_from_unrelated` (the drawn ones; the wander is random, the mirrored gestures
#: are whole templates).
UNRELATED = ("diagonal", "triangle", "spiral")


def told_from_unrelated(templates: dict[str, np.ndarray],
                        theta: float = 0.002) -> dict[str, dict[str, float]]:
    """Per gesture and unrelated motion (:data:`UNRELATED`), the earliest progress at which the
    gesture strays from every start of that motion (any size and tempo) by more than ``theta``
    metres: before it, a follower that recognises the gesture also drives that motion's start."""
    motions = unrelated_motions(np.random.default_rng(0), templates)
    return {g: {m: earliest(g, {g: templates[g], m: motions[m]}, theta) for m in UNRELATED}
            for g in templates}


#: What an action must pass before it drives (:mod:`behaviors.mop.follower`,
#: :mod:`behaviors.mop.validity`, :mod:`behaviors.mop.spotting`): engaged (past its onset),
#: accepted (not refused), covered (``coverage`` of its path), on its path (no misfit),
#: probable (``min_probability`` with the threshold model counted, or committed to by shape,
#: :meth:`~behaviors.mop.shape_lead.ShapeLead._committed`, which drives however improbable: the
#: circle drives at 0.26 of itself with a probability of 0.00-0.13), best (switch margin), leads
#: (in shape by ``shape_lead.LEAD``), unshared (its start no longer shared with another template
#: the input fits, :meth:`~behaviors.mop.spotting.GestureSpotting._shares`: what holds the line,
#: whose other gates all pass from about its reach, until 0.43-0.50 of it).
GATES = ("engaged", "accepted", "covered", "on_path", "probable", "best", "leads", "unshared")


def gate_state(f: ActionFollower, k: int) -> tuple[bool, ...]:
    """Which of :data:`GATES` template ``k`` passes after the follower's last step."""
    p = np.array([f._state.probabilities[n] for n in f.names]) * f._kept
    rivals = ~f._refused & (p >= shape_lead.RIVAL_PROBABILITY)
    rivals[k] = False
    need = shape_lead.LEAD * 2.0 * shape_lead.SHAPE_SPREAD ** 2   # as ShapeLead._leads
    lead = not rivals.any() or f._shape[rivals].min() - f._shape[k] >= need
    b = f.bank
    g = float(b.starts[k] + min(f.forward.mean[k], b.lengths[k] - 1.0))
    progress = np.array([f._state.progress_by[n] for n in f.names])
    return (bool(f._engaged[k]), not f._refused[k], bool(f._covered[k]), not f._misshaped[k],
            bool(p[k] >= f.min_probability or f._committed() == k), f._best == k, bool(lead),
            not f._shares(k, g, progress))


def gates(templates: dict[str, np.ndarray], rng: np.random.Generator,
          count: int) -> dict[str, dict[str, list[float]]]:
    """Per gesture and gate, the progress from which the gate held without a break until the
    gesture was recognised (or its last tick, when never), in ``count`` back-to-back sequences
    of four drawn as ``follow_quality.sequences`` draws them."""
    f = puck_follower(templates)
    out: dict[str, dict[str, list[float]]] = {g: {n: [] for n in GATES} for g in templates}
    for _ in range(count):
        x, truth, prog, order = back_to_back(rng, templates, 4)
        f.reset()
        ticks = []
        for s, g in zip(x, truth):
            st = f.step(s)
            ticks.append((st.valid and st.best == g, gate_state(f, f._index[g]) if g else None))
        for g in order:
            idx = [i for i, t in enumerate(truth) if t == g and np.isfinite(prog[i])]
            end = next((i for i in idx if ticks[i][0]), idx[-1])
            held = []
            for j, _ in enumerate(GATES):
                i = end
                while i > idx[0] and ticks[i - 1][1][j]:
                    i -= 1
                held.append(float(prog[i]) if ticks[end][1][j] else 1.0)
                out[g][GATES[j]].append(held[-1])
            if DEBUG:
                print(g, f"recognised {prog[end]:.2f}" if ticks[end][0] else "never",
                      dict(zip(GATES, np.round(held, 2))))
    return out


def indistinguishable(name: str, p: float, other: str, templates: dict[str, np.ndarray],
                      theta: float = 0.002, memo: dict | None = None) -> bool:
    """Whether gesture ``name``'s path up to progress ``p`` (noise-free) is still within
    ``theta`` metres of a start of ``other``'s at some size and tempo, or has not yet left its
    own start by ``theta``: no observer could tell ``other`` wrong there."""
    key = (name, round(p, 2), other)
    if memo is not None and key in memo:
        return memo[key]
    tpl = templates[name]
    prefix = at_phase(tpl, np.linspace(0, key[1] * (len(tpl) - 1), int(400 * key[1]) + 2))
    same = bool(np.max(np.linalg.norm(prefix - prefix[0], axis=1)) <= theta
                or closest_start(prefix, templates[other]) <= theta)
    if memo is not None:
        memo[key] = same
    return same


def main() -> None:
    check_flags("spotting_reach", sys.argv[1:])
    t0 = time.perf_counter()
    templates = gesture_templates()
    figures: dict[str, float] = {}
    for theta in (0.002, 0.004):
        mm = int(round(theta * 1000))
        at = {name: earliest(name, templates, theta) for name in templates}
        for name, p in at.items():
            figures[f"{name}_told_apart_progress_theta_{mm}mm"] = p
        figures[f"told_apart_before_20pct_share_theta_{mm}mm"] = float(
            np.mean([p < 0.2 for p in at.values()]))
        if mm == 2:
            reach = at
    # how long each gesture's start is also a start of an unrelated motion (at 2 mm)
    for name, by in told_from_unrelated(templates).items():
        for motion, p in by.items():
            figures[f"{name}_told_from_{motion}_progress_theta_2mm"] = p
    # beside it, the follower: each gesture's recognition in back-to-back sequences (the draws
    # bench/follow_quality.py compares options on), and the share recognised within 20% or, where
    # no observer can tell the gesture apart that early, by its reach at 2 mm
    record: list = []
    seq = sequences(puck_follower, templates, np.random.default_rng(OPTION_SEED), run, count=16,
                    record=record)
    # which wrong runs any observer could have avoided (indistinguishable, via sequences)
    for k in ("wrong_valid_longest_ticks_max", "wrong_valid_indistinguishable_share",
              "wrong_valid_avoidable_longest_ticks_max"):
        figures[k] = seq[f"sequence_{k}"]
    for name in templates:
        got = [p for g, p in record if g == name]
        figures[f"{name}_recognition_progress_median"] = float(np.median(got))
        figures[f"{name}_recognition_minus_reach_median"] = float(np.median(got)) - reach[name]
    # what holds each gesture back: the median progress from which each gate held
    for name, by_gate in gates(templates, np.random.default_rng(OPTION_SEED), 16).items():
        medians = {gate: float(np.median(v)) for gate, v in by_gate.items()}
        for gate, v in medians.items():
            figures[f"{name}_gate_{gate}_progress_median"] = v
        last = max(medians.values())   # the rules that clear at the same sample, all named
        print(f"{name}_last_gate".ljust(50), "+".join(g for g, v in medians.items() if v == last))
    figures["recognised_within_20pct_share"] = float(np.mean([p <= 0.2 for _, p in record]))
    figures["recognised_within_20pct_or_reach_share"] = float(np.mean([p <= max(0.2, reach[g])
                                                                       for g, p in record]))
    figures["bench_seconds"] = time.perf_counter() - t0
    for k, v in figures.items():
        print(f"{k:50s} {v:.4g}")
    emit("spotting_reach", figures, {})


if __name__ == "__main__":
    main()
