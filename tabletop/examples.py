"""Regenerate the shipped example behaviours from their scripted designers.

    python -m tabletop.examples [--out behaviors/library] [--check]

Writes ``<out>/<name>/behavior.yaml`` and ``demonstration.csv`` for lover, bully, playful_friend,
stalker and afraid. The demonstrations come from the seeded scripted designers in
:mod:`behaviors.puppet_master.designers`, so the output is the same byte for byte on every run.
``--check`` writes nothing and exits 1 if a shipped file differs from what would be written;
then it prints every behaviour's fidelity table (generated on unseen main paths beside its
demonstration, see :mod:`behaviors.puppet_master.fidelity`), naming the thresholds each
behaviour misses on each path, the same against a pursuing visitor for the characters shown
by chasing them, the thresholds met of all, the thresholds the scripted designer's own
character misses on the same paths and the misses that are the engine's alone (the report of
bench/fidelity.py's first seed, :func:`print_report`; it informs, the exit status is about the
files).
"""

from __future__ import annotations

import argparse
import functools
import sys
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from behaviors.puppet_master import designers, fidelity, visitors
from behaviors.puppet_master.engine import Behavior, Params
from behaviors.puppet_master.sequential import pair_takes
from tabletop import library

DEFAULT_OUT = Path(__file__).resolve().parent.parent / "behaviors" / "library"
SECONDS = 60.0
TABLE = (1.2, 0.8)
# the table each demonstration was made on is stored with it (Params.table_width / height)
PARAMETERS = {"rate_hz": 40.0, "window": 40, "table_width": TABLE[0], "table_height": TABLE[1]}
# a character's own parameters on top: the afraid character, chased into walls, fits its
# targets no nearer to an edge than its demonstration's median distance to one
# (Params.edge_percentile; table_boundary.fit_target has the figures)
OWN_PARAMETERS = {"afraid": {"edge_percentile": 50.0}}
# The afraid character's other parameters measured on top (its misses on the open paths, the
# engine's alone in brackets, seeds 0-5 + 8-13 + 26-31, against 24 (2) + 29 (3) + 30 (3) = 83
# (8), pursuit 42 + 42 + 43 = 127 of 144): ratio 0.5 96 (17) / 126, ratio 2 97 (12) / 129,
# smooth 4 100 (15) / 130, w_velocity 2 92 (8) / 129, window 30 94 (11) / 127, half_life 10 86
# (15) / 127, w_rel_look 0.5 97 (10) / 127. None kept.
# None for the lover: its misses beside slow mains (still/moving, speed, orbit) moved with no
# parameter beyond the bench's own spread (bench/fidelity.py --perturb 4: misses 16-18 / 13-15,
# the engine's alone 5-7 / 3-6 on seeds 0-5 / 8-13). Measured on the lover alone, misses (the
# engine's) on 0-5 / 8-13 against 16 (6) / 15 (6): ratio 0.5 14 (4) / 16 (6), 0.75 18 (7) /
# 20 (9); window 30 20 (7) / 19 (8), 60 19 (9) / 16 (8); smooth 4 20 (6) / 17 (7); catch_up 2
# 18 (5) / 15 (7), 0.5 19 (6) / 19 (7); relative_motion 0.07 21 (7) / 21 (10), 0.14 20 (7) /
# 15 (4); w_delta_direction 0.5 17 (5) / 15 (7); w_norm_look 0.5 17 (5) / 19 (6); balance_gain
# 0.05 17 (7) / 15 (6); w_rel_position 0.5 20 (6) / 21 (9), 0.75 23 (8) / 14 (4); w_rel_look
# 2 18 (6) / 14 (7); on 0-5 only: patch 24 19 (8), 32 20 (8); smooth 2 17 (4); ratio 2 18
# (4); half_life 10 17 (4); w_velocity 2 24 (5); w_rel_position 2 21 (6); w_rel_look 0.5 21
# (6); detail_levels 5 16 (5), 6 20 (9). The balance ratio for the others (0.5 / 0.75; 0-5 and
# 8-13 against 4 (2) / 6 (6), 1 (1) / 6 (6), 11 (5) / 13 (8)): bully 10 (7) / 9 (6) and 10 (9) /
# 9 (6), playful friend 4 (4) / 2 (2) and 2 (2) / 7 (7), stalker 16 (8) / 13 (7) and 13 (8) /
# 13 (7). smooth 4 (means of five runs, as --perturb 4): the stalker 11.0 (5.0) -> 12.6 (6.2)
# on 0-5 and 12.0 (7.2) -> 11.2 (6.4) on 8-13, the playful friend 2.2 (2.2) -> 3.4 (2.6) and
# 5.0 (5.0) -> 3.8 (3.8): better on the held-out seeds only, so the paper's 3 stays. One run
# each, 0-5 / 8-13: half_life 10 / 20 the stalker 13 (6) / 12 (6) and 17 (10) / 11 (6), the
# bully 10 (7) / 5 (3) and 5 (5) / 8 (7); w_velocity 0.5 stalker 23 (10) / 15 (9), bully 13 /
# 16 (12 / 12). The playful friend's window 80 / 160 (2 / 4 s, toward its sway's 4.8 s, see
# bench/fidelity.py) on seeds 0-5, 8-13, 26-31, one run each: misses (all contact) 11 / 10
# against 9, contact 0.037 +- 0.015 / 0.040 +- 0.018 against 0.038 +- 0.015; more coherence
# choices to hold the sway across darts, ratio 0.5 / 0.25: 8 / 20 (contact +- 0.017 / 0.020,
# runs on or off a dart lengthened). Not kept.
DESCRIPTIONS = {
    "lover": "Approaches the main character and stays close, facing it, nuzzling side to side.",
    "bully": "Lurks facing the main character, charges at it, pushes into it, then backs off.",
    "playful_friend": "Circles counter-clockwise around the main character, darting in and out.",
    "stalker": "Follows about 0.35 m behind the main character, watching it; stops when it stops.",
    "afraid": "Keeps half a metre away and flees when the main character comes closer.",
}


@functools.lru_cache(maxsize=None)
def example_demonstration(name: str) -> np.ndarray:
    """The scripted designer's demonstration for ``name``, rounded to micrometres/microradians
    (read-only: computed once per process)."""
    demo = designers.demonstrate(name, seconds=_seconds(name), rate_hz=PARAMETERS["rate_hz"],
                                 table=TABLE)
    out = np.round(demo, 6) + 0.0   # + 0.0 turns -0.0 into 0.0
    out.flags.writeable = False
    return out


def _seconds(name: str) -> float:
    """The length of ``name``'s demonstration (s): designers.DURATION_S's, else SECONDS."""
    return designers.DURATION_S.get(name, SECONDS)


def parameters(name: str) -> dict:
    """The behaviour parameters ``name`` is saved with: PARAMETERS and its OWN_PARAMETERS."""
    return {**PARAMETERS, **OWN_PARAMETERS.get(name, {})}


def _source(name: str) -> str:
    return (f"scripted designer behaviors.puppet_master.designers.demonstrate({name!r}, "
            f"seed={designers.SEEDS[name]}, seconds={_seconds(name):g}, "
            f"table={TABLE[0]:g}x{TABLE[1]:g} m)")


def example_files(name: str) -> dict[str, str]:
    """The file texts of one example behaviour: {file name: text}."""
    demo = example_demonstration(name)
    return {
        library.DEMONSTRATION_FILE: library.demonstration_csv(demo),
        library.BEHAVIOR_FILE: library.describe_yaml(name, demo, parameters(name),
                                                     description=DESCRIPTIONS[name],
                                                     source=_source(name)),
    }


def regenerate(out: Path, names: Sequence[str] = designers.PERSONALITIES) -> list[Path]:
    """Write every example into ``out`` (replacing earlier versions); returns the folders."""
    return [library.save_behavior(out, name, example_demonstration(name), parameters(name),
                                  description=DESCRIPTIONS[name], source=_source(name),
                                  replace=True)
            for name in names]


def differences(out: Path, names: Sequence[str] = designers.PERSONALITIES) -> list[str]:
    """Files under ``out`` that differ from (or are missing against) the regenerated ones."""
    bad = []
    for name in names:
        for fname, text in example_files(name).items():
            p = out / name / fname
            if not p.is_file() or p.read_text(encoding="utf-8") != text:
                bad.append(str(p))
    return bad


FIDELITY_COLUMNS = (
    ("distance_mean_m", "dist m"), ("speed_mean_mps", "speed"), ("speed_still_mps", "v still"),
    ("speed_moving_mps", "v moving"), ("still_moving_ratio", "still/mov"), ("facing", "facing"),
    ("look_change_rad", "dlook"), ("saturation", "satur."), ("texture_rad", "texture"),
    ("contact", "contact"), ("orbit_radps", "orbit"), ("edge_share", "at edge"))


Rows = dict[str, dict[str, dict]]


def _trained(folder: Path, name: str, perturb: float = 0.0) -> tuple[Behavior, dict]:
    """``name``'s behaviour from ``folder`` and its demonstration's figures; ``perturb``: its
    drift correction's share (Params.relative_motion) scaled by 1 + perturb."""
    stored = library.load_behavior(folder / name)
    params = dict(stored.parameters)
    if perturb:
        share = float(params.get("relative_motion", Params.relative_motion))
        params["relative_motion"] = share * (1.0 + perturb)
    behavior = Behavior.train(stored.demonstration, **params)
    # the shipped demonstrations were made on the bench's table (designers.demonstrate)
    return behavior, fidelity.demonstration_figures(behavior, (0.0, 0.0, *TABLE))


def fidelity_table(folder: Path = DEFAULT_OUT, names: Sequence[str] = designers.PERSONALITIES,
                   seconds: float = 40.0, seed: int = 0, perturb: float = 0.0) -> Rows:
    """{behaviour: {unseen path: compared row}} for the behaviours saved in ``folder``, on
    unseen main paths ``seconds`` long (``perturb``: see :func:`_trained`; bench/fidelity.py
    --perturb)."""
    paths = visitors.unseen_main_paths(seed, seconds, TABLE)
    out: Rows = {}
    for name in names:
        behavior, demo = _trained(folder, name, perturb)
        out[name] = {path: fidelity.evaluate(behavior, main, (0.0, 0.0, *TABLE), demo)
                     for path, main in paths.items()}
    return out


def pursuit_table(folder: Path = DEFAULT_OUT, names: Sequence[str] = designers.CHASED,
                  seconds: float = 40.0, seed: int = 0) -> Rows:
    """{behaviour: {visitors.PURSUIT: compared row}}: the characters whose demonstration shows
    them chased (designers.CHASED), generated against an unseen visitor going after them (a
    closed loop, visitors.Pursuer, ``seconds`` long), the situation their demonstration
    shows."""
    out: Rows = {}
    for name in names:
        behavior, demo = _trained(folder, name)
        out[name] = {visitors.PURSUIT: fidelity.evaluate_pursuit(
            behavior, visitors.pursuer(seed, seconds, TABLE), (0.0, 0.0, *TABLE), demo)}
    return out


def designer_table(seconds: float = 40.0, seed: int = 0, pursuit: bool = False,
                   folder: Path = DEFAULT_OUT) -> Rows:
    """The fidelity reference: {behaviour: {path: row}}, the scripted designer's own character
    (the policy that made the demonstration) on the same unseen paths (``pursuit``: against
    the pursuing visitor, for designers.CHASED), on the generation grid, compared with the
    demonstration's figures like a generation. A threshold it misses on a path is a figure of
    the situation, not of the engine."""
    out: Rows = {}
    names = designers.CHASED if pursuit else designers.PERSONALITIES
    paths = {} if pursuit else visitors.unseen_main_paths(seed, seconds, TABLE)
    for name in names:
        behavior, demo = _trained(folder, name)
        rate = behavior.params.rate_hz

        def row(t: np.ndarray, main: np.ndarray, react: np.ndarray) -> dict:
            return fidelity.compare(demo, fidelity.figures(main, react, rate,
                                                           behavior.turn_limit,
                                                           (0.0, 0.0, *TABLE)))
        if pursuit:
            out[name] = {visitors.PURSUIT: row(*designers.pursued_on_grid(
                name, visitors.pursuer(seed, seconds, TABLE), rate, TABLE))}
            continue
        out[name] = {}
        for path, main in paths.items():
            t, react = designers.reaction_on_grid(name, main, rate, TABLE)
            out[name][path] = row(t, fidelity.main_on_grid(main, t), react)
    return out


# sequential_comparison's second two-puck hand: the same designer's other hand (another shake,
# other choices) at the same reaction time, a figure of the spread between hands beside the
# rule's (SEQUENTIAL_ALLOWANCE, measured over four hands)
SECOND_HAND = 100


@functools.cache
def sequential_paths(seeds: tuple[int, ...], seconds: float) -> tuple[np.ndarray, ...]:
    """The open unseen main paths of ``seeds`` (``seconds`` long) the comparison runs on."""
    return tuple(m for s in seeds for m in visitors.unseen_main_paths(s, seconds, TABLE).values())


@functools.cache
def _sequential_takes(name: str) -> tuple[np.ndarray, np.ndarray]:
    """The scripted designer's sequential take of ``name`` (main, reactor), made once."""
    return designers.sequential_takes(name, designers.SEEDS[name], table=TABLE)


def _figures(name: str, demo: np.ndarray, paths: Sequence[np.ndarray]) -> tuple[int, float]:
    """(thresholds missed on ``paths``, mean generated distance to the main (m)) of ``demo``
    trained with ``name``'s shipped parameters, against its own demonstration."""
    behavior = Behavior.train(demo, **parameters(name))
    figures = fidelity.demonstration_figures(behavior)
    rows = [fidelity.evaluate(behavior, main, (0.0, 0.0, *TABLE), figures) for main in paths]
    return (sum(len(fidelity.failures(r)) for r in rows),
            float(np.mean([r["gen_distance_mean_m"] for r in rows])))


#: The two-puck references of :func:`sequential_comparison`: the designer's own hand, and its
#: hand SECOND_HAND seeds on (the range a hand alone moves the figures by).
REFERENCES = {"two_puck": 0, "second_hand": SECOND_HAND}


@functools.cache
def two_puck_figures(name: str, seeds: tuple[int, ...], seconds: float,
                     key: str = "two_puck") -> tuple[int, float]:
    """A two-puck reference of sequential_comparison (:func:`_figures` on
    :func:`sequential_paths`): ``key`` "two_puck", the designer's own hand, or "second_hand",
    its SECOND_HAND, both at the same reaction time on the reactor's camera frames (half a
    frame after the main take's), so that the sequential take differs from "two_puck" only by
    being paired from two takes (the playback seen a frame late)."""
    seed = designers.SEEDS[name]
    on_phase = designers.path_at(*designers.sequential_frames(name, seed, table=TABLE))
    return _figures(name, designers.demonstrate(name, seed + REFERENCES[key], rate_hz=60.0,
                                                table=TABLE, main=on_phase.copy()),
                    sequential_paths(seeds, seconds))


def sequential_comparison(name: str, seeds: tuple[int, ...], seconds: float = 40.0,
                          pair: Callable[[np.ndarray, np.ndarray], np.ndarray] = pair_takes,
                          references: tuple[str, ...] = tuple(REFERENCES)
                          ) -> dict[str, tuple[int, float]]:
    """Sequential training of ``name`` (designers.sequential_takes, paired by ``pair``) beside
    :func:`two_puck_figures`: {"sequential", and each of ``references`` ("two_puck",
    "second_hand"): (thresholds missed on the open main paths of ``seeds``, mean generated
    distance to the main (m))}. :func:`sequential_misses` reads "two_puck" alone."""
    return {"sequential": _figures(name, pair(*_sequential_takes(name)),
                                   sequential_paths(seeds, seconds)),
            **{key: two_puck_figures(name, seeds, seconds, key) for key in references}}


# (misses, m) a character's sequential behaviour may differ from its two-puck demonstration by
# (sequential_misses), sized for the test's 12 open paths of 20 s. Measured on the tuning
# seeds in four sets of that size (seeds 0-3, 4-5 + 8-9, 10-13, 26-29; 20 s), as the largest
# change that moves a two-puck demonstration without any pairing: the range among the
# designer's hands 0, 100, 200, 300 on its shipped main path (misses / mm: lover 6 / 5.1, bully
# 13 / 25.7, playful friend 6 / 3.3, stalker 6 / 2.5, afraid 10 / 53.9), sequential against
# two-puck on two of its other main paths (seed +1, +2: 7 / 4.6, 7 / 9.6, 4 / 4.8, 5 / 4.2, 9 /
# 25.3) and a reaction one frame (17 ms, the playback seen a frame late) slower on the shipped
# and those two paths (5 / 3.5, 7 / 16.4, 4 / 4.4, 11 / 4.4, 9 / 27.0). The afraid's misses are
# not judged (None): its designer flees on half a frame, so a reactor paired 0.1-0.2 s early or
# late moves them by -4 to +7 in those sets, inside its hands' range of 10, and its sequential
# take on the test's paths sits at that range (+10).
SEQUENTIAL_ALLOWANCE: dict[str, tuple[int | None, float]] = {
    "lover": (7, 0.0051), "bully": (13, 0.0257), "playful_friend": (6, 0.0048),
    "stalker": (11, 0.0044), "afraid": (None, 0.0539)}


def sequential_misses(name: str, figures: dict[str, tuple[int, float]]) -> list[str]:
    """What a sequential behaviour misses of the rule, with its figures: no more misses than
    the two-puck demonstration of the same hand plus ``name``'s SEQUENTIAL_ALLOWANCE, its mean
    generated distance within that allowance's metres of two-puck's."""
    (seq_n, seq_d), (two_n, two_d) = figures["sequential"], figures["two_puck"]
    extra_n, extra_d = SEQUENTIAL_ALLOWANCE[name]
    out = []
    if extra_n is not None and seq_n > two_n + extra_n:
        out.append(f"misses {seq_n} against {two_n} + {extra_n}")
    if abs(seq_d - two_d) > extra_d:
        out.append(f"distance {seq_d:.4f} against {two_d:.4f} +- {extra_d}")
    return out


def print_designer(reference: Rows) -> None:
    """One line per behaviour: the thresholds the designer's own character misses per path."""
    for name, paths in reference.items():
        print(f"  {name:16s}" + "".join(f"{path}: {','.join(fidelity.failures(row)) or '-'}   "
                                        for path, row in paths.items()))


def print_fidelity(table: Rows) -> None:
    """Print one table per behaviour: the demonstration's figures, then each path's."""
    for name, rows in table.items():
        print(f"{name}:")
        print(f"  {'':22s}" + "".join(f"{h:>10s}" for _, h in FIDELITY_COLUMNS)
              + f"{'dist W1':>10s}{'sect TV':>10s}{'speed W1':>10s}  misses")
        first = next(iter(rows.values()))
        print(f"  {'demonstration':22s}" + "".join(f"{first['demo_' + k]:10.3f}"
                                                     for k, _ in FIDELITY_COLUMNS))
        for path, row in rows.items():
            print(f"  {path:22s}" + "".join(f"{row['gen_' + k]:10.3f}" for k, _ in FIDELITY_COLUMNS)
                  + f"{row['distance_w1_m']:10.3f}{row['sectors_tv']:10.3f}"
                  + f"{row['speed_w1_mps']:10.3f}  {','.join(fidelity.failures(row)) or '-'}")


def summary(table: Rows, reference: Rows) -> str:
    """One line: the thresholds ``table`` meets, the behaviour/path pairs that miss one, and
    how many of the misses are the engine's alone (its designer's own character, ``reference``,
    meets them on the same path; fidelity.engine_misses), and how many of the thresholds met
    are event thresholds met only through their floor (fidelity.floor_only)."""
    passed, pairs, per_threshold, met = fidelity.tally(table)
    total = pairs * len(per_threshold)
    engine = fidelity.count(fidelity.engine_misses(table, reference))
    floored = len(fidelity.floor_only_table(table))
    return (f"fidelity: {met} of {total} thresholds met, {pairs - passed} of {pairs} "
            f"behaviour/path pairs miss at least one; {engine} of the {total - met} misses are "
            f"the engine's alone (the designer's own character meets them); {floored} event "
            "thresholds met only through their floor (missed at 30% of the demonstration's "
            "alone)")


def print_report(table: Rows, pursuit: Rows, reference: Rows, pursuit_reference: Rows) -> None:
    """The fidelity report that bench/fidelity.py and ``--check`` print: the tables on the
    open paths and against a pursuing visitor, each with its :func:`summary`, the thresholds
    the designer's own character misses on the same paths, and the misses that are the
    engine's alone."""
    print_fidelity(table)
    print(summary(table, reference))
    print("against a visitor going after the character (as its demonstration shows it):")
    print_fidelity(pursuit)
    print(summary(pursuit, pursuit_reference))
    print("the designer's own character on the same paths (thresholds it misses):")
    print_designer(reference)
    print_designer(pursuit_reference)
    print("misses of the generation where the designer's own character meets the threshold "
          "(the engine's):")
    engine = fidelity.engine_misses(table, reference)
    chased = fidelity.engine_misses(pursuit, pursuit_reference)
    for name, paths in {**engine, **{f"{k} (pursuit)": v for k, v in chased.items()}}.items():
        print(f"  {name:18s}" + "".join(f"{path}: {','.join(v)}   "
                                        for path, v in paths.items()))


MAX_FIDELITY_S = 3600.0   # seconds of each unseen main path the --check table may ask for


def fidelity_seconds(text: str) -> float:
    """``--fidelity-seconds``: 0 (no table) or 1 to MAX_FIDELITY_S seconds, refused otherwise:
    1e9 asks for a 224 GiB path and inf, 0.01 (paths of under two samples) end in a traceback;
    nan and negative values would print no table, silently."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if v != 0 and not 1.0 <= v <= MAX_FIDELITY_S:
        raise argparse.ArgumentTypeError(
            f"{text!r}: give 0 (no fidelity table) or 1 to {MAX_FIDELITY_S:g} seconds")
    return v


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tabletop.examples",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help="library folder to write")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 if the shipped files differ")
    parser.add_argument("--fidelity-seconds", type=fidelity_seconds, default=40.0, metavar="S",
                        help="with --check: seconds of each unseen main path the fidelity "
                             "table is measured on (0: no table; default 40)")
    args = parser.parse_args(argv)
    try:
        if args.check:
            bad = differences(args.out)
            for p in bad:
                print(f"differs: {p}")
            print("examples up to date" if not bad else f"{len(bad)} file(s) differ")
            if bad:
                return 1
            if args.fidelity_seconds > 0:
                secs = args.fidelity_seconds
                print_report(fidelity_table(args.out, seconds=secs),
                             pursuit_table(args.out, seconds=secs),
                             designer_table(secs, folder=args.out),
                             designer_table(secs, pursuit=True, folder=args.out))
            return 0
        for folder in regenerate(args.out):
            print(f"wrote {folder}")
    except library.LibraryError as exc:
        print(f"python -m tabletop.examples: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
