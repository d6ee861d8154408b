"""``tabletop behave --fidelity``: how well the engine keeps a designer's own demonstration.

Instead of generating for one main path (--input, --out), the behaviour ``--train`` gives
(with ``--param``) is generated on the unseen main paths of the fidelity bench
(visitors.unseen_main_paths: a slow hand with pauses at 30 Hz, a fast one that reverses at
60 Hz, loops with spins in place at 45 Hz; ``--seconds`` each, drawn from ``--seed``) on the
reactor's table (``--pursuit``: and against the bench's visitor going after the character, a
closed loop, the situation a fleeing character is shown in), and the fidelity table is
printed: the demonstration's figures beside each path's, with the thresholds each path misses
(behaviors/puppet_master/fidelity.py). Where the demonstration is a shipped one of a
scripted designer (a library folder or its CSV, unchanged, on its table), the thresholds the
designer's own character misses on the same paths and the misses that are the engine's alone
are added, as ``python -m tabletop.examples --check`` says them; elsewhere there is no such
reference and they are left out.

Times in seconds, positions in table metres.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from tabletop.commands import number_in_range
from tabletop.errors import InputError

if TYPE_CHECKING:
    import numpy as np

    from behaviors.puppet_master.engine import Behavior

# seconds of each unseen path: 20 s keeps the table to about 3 s of generation beside the
# 2 s every command takes to start (4-6 s in all on one core); the bench's 40 s halves the
# spread of the event figures between seeds
DEFAULT_SECONDS = 20.0
SECONDS_RANGE = (1.0, 3600.0)   # the same cap as python -m tabletop.examples --fidelity-seconds
MAX_SEED = 999_999
# metres: the least table side the unseen paths are drawn on, twice the loops' margin from the
# edges (visitors.loops_and_spins: spots drawn 0.25 m in); on less they could not be drawn
MIN_TABLE_M = 0.5

Table = tuple[float, float, float, float]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--fidelity", action="store_true",
                        help="instead of --input/--out: print how well the engine keeps the "
                             "demonstration (--param applied) on unseen main paths, its "
                             "figures beside the generated ones with the thresholds missed "
                             "(behaviors/puppet_master/fidelity.py); about 5 s")
    parser.add_argument("--seconds", default=None, metavar="S",
                        help=f"with --fidelity: seconds of each unseen main path (default "
                             f"{DEFAULT_SECONDS:g}, {SECONDS_RANGE[0]:g} to "
                             f"{SECONDS_RANGE[1]:g})")
    parser.add_argument("--seed", default=None, metavar="N",
                        help="with --fidelity: which unseen main paths (default 0, as the "
                             "first seed of bench/fidelity.py)")
    parser.add_argument("--pursuit", action="store_true",
                        help="with --fidelity: one row more, against an unseen visitor going "
                             "after the character (as a fleeing character is shown; "
                             "visitors.Pursuer, 50 Hz), about 1 s more")


def options(args: argparse.Namespace, error: type[InputError]) -> tuple[float, int] | None:
    """(seconds, seed) of --fidelity, None for a generation (--input and --out), checked
    before any file is read; a mix of the two, a generation missing one of its files, or
    seconds or a seed out of range raises ``error`` with one line."""
    if args.fidelity:
        given = [o for o, v in (("--input", args.input), ("--out", args.out)) if v is not None]
        if given:
            raise error(f"--fidelity prints the fidelity table instead of generating for a "
                        f"main path: give it without {' and '.join(given)}")
        seconds = number_in_range(DEFAULT_SECONDS if args.seconds is None else args.seconds,
                                  "--seconds", "seconds", *SECONDS_RANGE, error)
        seed = number_in_range(0 if args.seed is None else args.seed, "--seed", "seeds", 0,
                               MAX_SEED, error, integer=True)
        return seconds, int(seed)
    alone = [o for o, v in (("--seconds", args.seconds), ("--seed", args.seed),
                            ("--pursuit", args.pursuit or None)) if v is not None]
    if alone:
        raise error(f"{' and '.join(alone)} go{'es' if len(alone) == 1 else ''} with "
                    "--fidelity (the fidelity table's unseen main paths)")
    missing = [o for o, v in (("--input", args.input), ("--out", args.out)) if v is None]
    if missing:
        raise error(f"the following arguments are required: {', '.join(missing)} (or "
                    "--fidelity, for the fidelity table instead)")
    return None


def unseen_paths(seed: int, seconds: float, table: Table) -> dict:
    """The fidelity bench's unseen main paths {name: (n, 4) t, x, y, dir} drawn on ``table``
    (x0, y0, x1, y1; metres)."""
    from behaviors.puppet_master import visitors
    x0, y0, x1, y1 = table
    paths = visitors.unseen_main_paths(seed, seconds, (x1 - x0, y1 - y0))
    for main in paths.values():
        main[:, 1] += x0
        main[:, 2] += y0
    return paths


class Pursuer:
    """visitors.pursuer (``times``, ``rate_hz``, ``first``, ``step``) on a table whose corner
    is (x0, y0) instead of the origin (the demonstration's bounds): poses shifted out of it,
    the reactor's shifted into it."""

    def __init__(self, seed: int, seconds: float, table: Table) -> None:
        import numpy as np

        from behaviors.puppet_master import visitors
        x0, y0, x1, y1 = table
        self.hand = visitors.pursuer(seed, seconds, (x1 - x0, y1 - y0))
        self.times, self.rate_hz = self.hand.times, self.hand.rate_hz
        self.shift = np.array([x0, y0, 0.0])

    def first(self) -> np.ndarray:
        return self.hand.first() + self.shift

    def step(self, i: int, prev: np.ndarray | None, react: np.ndarray) -> np.ndarray:
        return self.hand.step(i, None, react[:2] - self.shift[:2]) + self.shift


def fidelity_rows(behavior: Behavior, paths: dict, table: Table,
                  pursuit: tuple[int, float] | None = None) -> dict:
    """{path: compared row} of ``behavior`` generated on each of ``paths`` (fidelity.evaluate)
    against its own demonstration, made on ``table``; ``pursuit`` (seed, seconds): and
    against the pursuing visitor (visitors.PURSUIT, fidelity.evaluate_pursuit)."""
    from behaviors.puppet_master import fidelity, visitors
    demo = fidelity.demonstration_figures(behavior, table)
    out = {path: fidelity.evaluate(behavior, main, table, demo) for path, main in paths.items()}
    if pursuit is not None:
        out[visitors.PURSUIT] = fidelity.evaluate_pursuit(behavior, Pursuer(*pursuit, table),
                                                          table, demo)
    return out


def scripted_designer(args: argparse.Namespace, table: Table) -> str | None:
    """The personality whose scripted designer made the demonstration --train names (a
    shipped folder or its CSV, its demonstration unchanged, played on the table it was made
    on), else None."""
    import numpy as np

    from behaviors.puppet_master import designers
    from tabletop import examples, library
    if args.train is None or table != (0.0, 0.0, *examples.TABLE):
        return None
    path = Path(args.train)
    name = path.name if path.is_dir() else path.parent.name
    if name not in designers.PERSONALITIES:
        return None
    demo = (library.load_behavior(path).demonstration if path.is_dir()
            else library.read_demonstration(path))
    shipped = examples.example_demonstration(name)
    return name if demo.shape == shipped.shape and np.array_equal(demo, shipped) else None


def designer_rows(name: str, behavior: Behavior, paths: dict, table: Table,
                  pursuit: tuple[int, float] | None = None) -> dict:
    """{path: compared row} of the scripted designer's own ``name`` on ``paths`` (and against
    the pursuing visitor of ``pursuit``, (seed, seconds)), on the generation grid, against the
    demonstration's figures (examples.designer_table)."""
    from behaviors.puppet_master import designers, fidelity, visitors
    demo = fidelity.demonstration_figures(behavior, table)
    rate = behavior.params.rate_hz

    def row(main: np.ndarray, react: np.ndarray) -> dict:
        return fidelity.compare(demo, fidelity.figures(main, react, rate, behavior.turn_limit,
                                                       table))
    out = {}
    for path, main in paths.items():
        t, react = designers.reaction_on_grid(name, main, rate, (table[2], table[3]))
        out[path] = row(fidelity.main_on_grid(main, t), react)
    if pursuit is not None:
        _, main, react = designers.pursued_on_grid(name, Pursuer(*pursuit, table), rate,
                                                   (table[2], table[3]))
        out[visitors.PURSUIT] = row(main, react)
    return out


def summary(rows: dict) -> str:
    """One line without a designer's reference: the thresholds met, the paths that miss one,
    the event thresholds met only through their floor (fidelity.floor_only)."""
    from behaviors.puppet_master import fidelity
    passed, pairs, per_threshold, met = fidelity.tally({"": rows})
    floored = len(fidelity.floor_only_table({"": rows}))
    return (f"fidelity: {met} of {pairs * len(per_threshold)} thresholds met, "
            f"{pairs - passed} of {pairs} paths miss at least one; {floored} event thresholds "
            "met only through their floor (missed at 30% of the demonstration's alone)")


THRESHOLDS = ("thresholds: facing within 0.1 of the demonstration's; look change (dlook) and "
              "texture 0.67-1.5x; speed W1 within 20% of its mean speed; contact, still/mov "
              "and orbit within 30% (or a floor near 0); saturation at most its + 0.1")


def main(args: argparse.Namespace, seconds: float, seed: int, behavior: Behavior,
         table: Table, source: str, error: type[InputError] = InputError) -> int:
    """Print the fidelity table of the trained ``behavior`` on its ``table`` (the unseen
    paths ``seconds`` long, drawn from ``seed``; ``source``: the demonstration's file(s)); 0.
    A table too small for the paths raises ``error`` (the command's argument error)."""
    from behaviors.puppet_master import fidelity
    from tabletop import examples

    w, h = table[2] - table[0], table[3] - table[1]
    if min(w, h) < MIN_TABLE_M:
        raise error(
            f"--fidelity: the table is {w:.3g} x {h:.3g} m; the unseen main paths need "
            f"{MIN_TABLE_M:g} m a side (give --table W,H, the table the character plays on)")
    paths = unseen_paths(seed, seconds, table)
    pursuit = (seed, seconds) if args.pursuit else None
    rows = fidelity_rows(behavior, paths, table, pursuit)
    print(f"{source}: the demonstration beside its generation on unseen main paths "
          f"({seconds:g} s each, seed {seed}, table {w:g} x {h:g} m, "
          f"{behavior.params.rate_hz:g} Hz)")
    label = Path(args.train).stem if args.train is not None else "sequential take"
    table_rows = {label: rows}
    examples.print_fidelity(table_rows)
    name = scripted_designer(args, table)
    if name is None:
        print(summary(rows))
    else:
        reference = {label: designer_rows(name, behavior, paths, table, pursuit)}
        print(examples.summary(table_rows, reference))
        print(f"the scripted designer's own {name} on the same paths (thresholds it misses):")
        examples.print_designer(reference)
        engine = fidelity.engine_misses(table_rows, reference)
        print("misses where the designer's own character meets the threshold (the engine's): "
              + ("; ".join(f"{path}: {','.join(v)}" for paths_ in engine.values()
                           for path, v in paths_.items()) or "none"))
    print(THRESHOLDS)
    return 0
