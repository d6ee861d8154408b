"""``tabletop behave``: train a Puppet Master behaviour and generate a reactor for a main path."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from tabletop.commands import behave_fidelity
from tabletop.commands import (number_in_range, number_pair, output_file, sparse_hint,
                               thousandths_hint, warn_sparse_times)
from tabletop.errors import InputError

if TYPE_CHECKING:
    import numpy as np

    from behaviors.puppet_master.engine import Behavior

HELP = ("train a reactive behaviour from a demonstration CSV and generate the reactor's motion "
        "for a main character's path, causally, at the generation rate")

DEMO_COLUMNS = ("t", "main_x", "main_y", "main_dir", "react_x", "react_y", "react_dir")
MAIN_COLUMNS = ("t", "main_x", "main_y", "main_dir")
OUT_COLUMNS = ("t", "react_x", "react_y", "react_dir")


def _positions(columns: tuple[str, ...]) -> tuple[str, ...]:
    """The columns of ``columns`` that are table positions (metres)."""
    return tuple(c for c in columns if c.endswith(("_x", "_y")))


class BehaveArgumentError(InputError):
    """A bad ``behave`` argument."""


def param_names() -> list[str]:
    """The names ``--param`` takes: every field of behaviors.puppet_master.params.Params."""
    from dataclasses import fields

    from behaviors.puppet_master.params import Params
    return sorted(f.name for f in fields(Params))


# what a parameter's default of 0 stands for, where it is not a plain zero
ZERO_MEANS = {"max_turn_rate": "the demonstration's", "table_width": "the demonstration's area",
              "table_height": "the demonstration's area", "edge_percentile": "off",
              "half_life": "off", "w_room": "off"}


def param_defaults() -> str:
    """Every ``--param`` name with its default and unit, for the help: "ratio (1), window (40
    samples), ..." (the help listed the names alone: a designer had to open params.py to see
    where a parameter starts from)."""
    from behaviors.puppet_master.params import UNITS, Params
    units = {**UNITS, "rate_hz": "Hz"}
    out = []
    for name in param_names():
        value = getattr(Params(), name)
        said = ZERO_MEANS[name] if value == 0 and name in ZERO_MEANS else \
            f"{value:g}" + (f" {units[name]}" if name in units else "")
        out.append(f"{name} ({said})")
    return ", ".join(out)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--train", metavar="DEMO.csv",
                        help="demonstration: t,main_x,main_y,main_dir,react_x,react_y,react_dir "
                             "(seconds, table metres, radians), any sampling rate; or a "
                             "behaviour folder (LIBRARY/NAME): its demonstration with its "
                             "parameters, as the installation plays it")
    parser.add_argument("--train-main", metavar="MAIN_TAKE.csv",
                        help="sequential training, instead of --train: the main demonstrated "
                             "first, t,main_x,main_y,main_dir (seconds, table metres, radians)")
    parser.add_argument("--train-react", metavar="REACT_TAKE.csv",
                        help="sequential training: the reactor demonstrated against the main "
                             "take's playback, t,react_x,react_y,react_dir, t on the main take's "
                             "times (seconds, table metres, radians)")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="a behaviour parameter (repeatable), e.g. --param ratio=2, over a "
                             "behaviour folder's own; NAME is one of (default): "
                             f"{param_defaults()}; their ranges and why: "
                             "behaviors/puppet_master/params.py")
    parser.add_argument("--input", metavar="MAIN.csv",
                        help="main character's path: t,main_x,main_y,main_dir (seconds, "
                             "table metres, radians), any rate (required but with --fidelity)")
    parser.add_argument("--out", metavar="REACT.csv",
                        help="output: t,react_x,react_y,react_dir, one row per generation step "
                             "(required but with --fidelity)")
    parser.add_argument("--rate", default=None, metavar="HZ",
                        help="generation rate in Hz (default: a behaviour folder's "
                             "rate_hz, else 40)")
    parser.add_argument("--table", default=None, metavar="W,H",
                        help="table size in metres from the origin; the reactor stays on it "
                             "(default: a behaviour folder's table_width,table_height, else the "
                             "bounds of the demonstration's positions)")
    behave_fidelity.add_arguments(parser)


MAX_RATE_HZ = 1000.0   # generation steps per second (the behaviours are made at 40)
MAX_ROWS = 2_000_000   # output rows (14 h of main path at 40 Hz)
TABLE_M = (0.05, 20.0)  # metres: a table side, as config.yaml's table section


def parse_rate(text: str) -> float:
    """A rate in Hz from 1 to MAX_RATE_HZ."""
    return number_in_range(text, "--rate", "Hz", 1.0, MAX_RATE_HZ, BehaveArgumentError)


def parse_table(text: str) -> tuple[float, float, float, float]:
    """``W,H`` in metres -> (0, 0, W, H)."""
    w, h = number_pair(text, "--table", "W,H in metres, e.g. 1.6,1.0", BehaveArgumentError)
    check_table(f"--table {text!r}", w, h)
    return 0.0, 0.0, w, h


def check_table(what: str, *sides: float) -> None:
    """Table ``sides`` (metres) within TABLE_M; else BehaveArgumentError naming ``what``."""
    lo, hi = TABLE_M
    if not all(math.isfinite(s) and lo <= s <= hi for s in sides):
        raise BehaveArgumentError(f"{what}: width and height must be metres from {lo:g} to "
                                  f"{hi:g}" + thousandths_hint("metres", lo, hi, *sides))


TABLE_PARAMS = ("table_width", "table_height")


def table_from_params(given: dict[str, float | int],
                      params: dict[str, float | int]) -> tuple[float, float, float, float] | None:
    """The table (0, 0, W, H) that ``params`` (given over stored) name, None where neither
    side is over 0 (the demonstration's bounds). One side alone ``given`` on the command line,
    the other neither given nor stored, raises BehaveArgumentError: Behavior takes a table
    only with both, and the one given was ignored."""
    w, h = float(params.get("table_width", 0.0)), float(params.get("table_height", 0.0))
    if w > 0.0 and h > 0.0:
        return 0.0, 0.0, w, h
    if w > 0.0 or h > 0.0:
        one, other = TABLE_PARAMS if w > 0.0 else TABLE_PARAMS[::-1]
        if one in given:
            raise BehaveArgumentError(
                f"--param {one}={given[one]:g} without {other}: the table the demonstration "
                f"was made on needs both, e.g. --param table_width=1.6 --param table_height=1.0")
    return None


def parse_params(items: list[str]) -> dict[str, float | int]:
    """``NAME=VALUE`` items as behaviour parameters, typed as the Params field is; an unknown
    name or a value of the wrong kind raises BehaveArgumentError naming it."""
    from dataclasses import fields

    from behaviors.puppet_master.params import Params, unknown_names

    kinds = {f.name: f.type for f in fields(Params)}
    out: dict[str, float | int] = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise BehaveArgumentError(f"--param {item!r} must be NAME=VALUE, e.g. ratio=2")
        if name not in kinds:
            raise BehaveArgumentError(f"--param {unknown_names([name], set(kinds))}: unknown "
                                      "parameter; known: "
                                      f"{', '.join(sorted(kinds))}")
        integer = kinds[name] in (int, "int")
        try:
            value: float | int = int(text) if integer else float(text)
        except ValueError:
            raise BehaveArgumentError(f"--param {name}={text!r}: expected "
                                      f"{'an integer' if integer else 'a number'}") from None
        if name in out:
            raise BehaveArgumentError(f"--param {name} is given twice")
        if name in TABLE_PARAMS and value != 0:      # 0: none, the demonstration's bounds
            check_table(f"--param {name}={text!r}", value)
        out[name] = value
    return out


def read_rows(path: str, columns: tuple[str, ...], what: str, min_rows: int,
              max_bytes: int | None = None) -> np.ndarray:
    """The rows (n, len(columns)) of CSV ``path``, in ``columns``' order, its times (the first
    column) strictly increasing and its positions on no absurd scale; errors name the line.
    ``max_bytes``: the most such a file holds (else any text file's cap)."""
    from tabletop.files import (MAX_TEXT_BYTES, check_increasing, check_positions,
                                read_csv_lines)

    header, rows, lines = read_csv_lines(path, columns, what=what, min_rows=min_rows,
                                         max_bytes=max_bytes or MAX_TEXT_BYTES)
    rows = rows[:, [header.index(c) for c in columns]]
    check_increasing(rows[:, 0], path, lines=lines)
    check_positions(rows, columns, _positions(columns), path, lines=lines)
    return rows


def check_metres(xy: np.ndarray, source: str, what: str) -> None:
    """Positions (n, 2) that span more than any table side (TABLE_M, metres), or lie farther
    than that from the origin (the table's corner), are refused: recorded in millimetres, a
    demonstration trained a reactor hundreds of metres from a main given in metres, without a
    word; a main in millimetres that barely moves spans less than 20 and is caught by where
    it lies."""
    import numpy as np
    span = np.ptp(xy, axis=0)
    if float(span.max()) > TABLE_M[1]:
        raise BehaveArgumentError(
            f"{source}: the {what} positions span {span[0]:.4g} x {span[1]:.4g} m, more than "
            f"any table ({TABLE_M[1]:g} m); positions are table metres (millimetres given?)")
    far = np.abs(xy).max(axis=0)
    if float(far.max()) > TABLE_M[1]:
        raise BehaveArgumentError(
            f"{source}: the {what} positions reach {far[0]:.4g} x {far[1]:.4g} m from the "
            f"origin, beyond any table side ({TABLE_M[1]:g} m); positions are table metres "
            "(millimetres given?)")


def warn_still_reactor(demo: np.ndarray, source: str) -> None:
    """One line on stderr when the demonstration's reactor never moved nor turned (as a take
    the studio refuses: the reactor puck left lying while the main moved); the reactor
    generated from it hardly moves (only pushed aside by its main), which was made without
    a word."""
    import sys

    from tabletop.studio.pm_take import STILL_M, STILL_RAD, reach
    far, turn = reach(demo, (4, 5, 6))
    if far < STILL_M and turn < STILL_RAD:
        print(f"tabletop behave: warning: {source}: the demonstration's reactor never moves "
              f"({far * 100:.1f} cm from its first pose, turned {turn:.2f} rad): the reactor "
              "generated hardly moves", file=sys.stderr)


def warn_degrees(rows: np.ndarray, columns: dict[str, int], source: str) -> None:
    """One stderr line per direction column of ``rows`` beyond a turn (2 pi) but within 360:
    degrees given for radians, which trained a look turning about a radian a step (facing
    its main 14% of the time against 100%) without a word. A direction unwrapped past a
    turn in radians is read right; the line asks."""
    import sys

    import numpy as np
    for name, col in columns.items():
        far = float(np.max(np.abs(rows[:, col])))
        if 2 * math.pi + 1e-6 < far <= 360.0 + 1e-6:
            print(f"tabletop behave: warning: {source}: column {name!r} reaches {far:g}; "
                  "directions are radians (degrees given?)", file=sys.stderr)


def check_library_path(path: Path) -> None:
    """``--train`` naming a library instead of one of its behaviours, or a behaviour the
    library does not have (a typo: "lovr"), is refused naming the library's behaviours, not
    only "behavior.yaml: not found" or "demonstration CSV not found"; naming a folder's
    behavior.yaml, with the folder and its demonstration CSV to give instead."""
    import difflib

    from tabletop import library
    if path.name == library.BEHAVIOR_FILE and path.is_file():
        # a behaviour folder's own file, not a CSV: said so, not "expected header t,main_x..."
        try:
            demo = f" or its demonstration CSV ({library.load_behavior(path.parent).data_file})"
        except library.LibraryError:
            demo = ""
        raise BehaveArgumentError(f"--train {path}: a behaviour file, not a demonstration CSV; "
                                  f"give its folder (--train {path.parent}){demo}")
    if path.is_dir() and not (path / library.BEHAVIOR_FILE).exists():
        lib, name = path, ""
    elif not path.exists() and path.parent.is_dir() and not path.suffix:
        lib, name = path.parent, path.name
    else:
        return
    try:
        names = library.list_behaviors(lib)
    except library.LibraryError:
        return
    if not names:
        return
    listed = ", ".join(names[:12]) + (", ..." if len(names) > 12 else "")
    if not name:
        raise BehaveArgumentError(f"--train {path}: a behaviour library, not a behaviour; give "
                                  f"one of its folders, e.g. {path / names[0]} ({listed})")
    close = difflib.get_close_matches(name, names, n=1)
    hint = f"did you mean {lib / close[0]}? " if close else ""
    raise BehaveArgumentError(f"--train {path}: no such behaviour; {hint}the library has "
                              f"{listed}")


def read_folder(folder: str, out: str | None) -> tuple[np.ndarray, dict[str, float | int]]:
    """A Puppet Master behaviour folder's demonstration (n, 7) and stored parameters; ``out``
    (--out, None with --fidelity) must not be one of its files."""
    from tabletop import library

    stored = library.load_behavior(folder)
    if stored.kind != "puppet_master":
        raise BehaveArgumentError(f"{folder}: a {stored.kind} behaviour, not a puppet_master one")
    if out is not None:
        output_file(out, "--out", BehaveArgumentError, example="react.csv",
                    inputs=(Path(folder) / library.BEHAVIOR_FILE, stored.data_file))
    return stored.demonstration, dict(stored.parameters)


def read_demonstration(args: argparse.Namespace
                       ) -> tuple[np.ndarray, dict[str, float | int], str]:
    """The demonstration (n, 7) from --train (a CSV, or a behaviour folder with its stored
    parameters), or paired from --train-main and --train-react; the stored parameters ({} but
    for a folder); and the file(s) its errors name."""
    import sys

    from behaviors.puppet_master.sequential import TakeError, left_out, pair_takes
    from tabletop.file_io import MAX_DEMONSTRATION_BYTES

    if (args.train is None) == (args.train_main is None and args.train_react is None):
        raise BehaveArgumentError("give either --train DEMO.csv or both --train-main and "
                                  "--train-react")
    if args.train is not None:
        check_library_path(Path(args.train))
    if args.train is not None and Path(args.train).is_dir():
        return *read_folder(args.train, args.out), args.train
    if args.train is not None:
        return (read_rows(args.train, DEMO_COLUMNS, "demonstration CSV", 2,
                          MAX_DEMONSTRATION_BYTES), {}, args.train)
    if args.train_main is None or args.train_react is None:
        raise BehaveArgumentError("sequential training needs both --train-main and --train-react")
    takes = []
    for path, cols in ((args.train_main, MAIN_COLUMNS), (args.train_react, OUT_COLUMNS)):
        takes.append(read_rows(path, cols, "take CSV", 2, MAX_DEMONSTRATION_BYTES))
    try:   # what the paired demonstration says (too short, no area) is of both takes
        demo = pair_takes(*takes)
    except TakeError as exc:
        raise BehaveArgumentError(f"{args.train_main}, {args.train_react}: {exc}") from None
    note = left_out(*takes)
    if note:
        print(f"tabletop behave: warning: {args.train_react}: {note}", file=sys.stderr)
    return demo, {}, f"{args.train_main}, {args.train_react} (paired)"


def main(args: argparse.Namespace) -> int:
    from behaviors.puppet_master.fidelity import generate
    from tabletop.files import write_csv

    table_of = behave_fidelity.options(args, BehaveArgumentError)
    if table_of is not None:      # --fidelity: (seconds, seed) of its unseen main paths
        return behave_fidelity.main(args, *table_of, *train(args, None)[:3],
                                     error=BehaveArgumentError)
    behavior, table, _, main_rows = train(args, args.input)
    rows = generate(behavior, main_rows, table)
    write_csv(args.out, OUT_COLUMNS, rows.tolist())
    return 0


def train(args: argparse.Namespace, main_path: str | None
          ) -> tuple[Behavior, tuple[float, float, float, float], str, np.ndarray | None]:
    """The behaviour ``args`` train (--train or the sequential takes, --param over a folder's
    own), the table (x0, y0, x1, y1) in metres its reactor stays on, the file(s) the
    demonstration came from and the rows of ``main_path`` (the main path CSV, --input; None
    with --fidelity, which makes its own)."""
    from behaviors.puppet_master.engine import Behavior, ParameterError
    from behaviors.puppet_master.params import Params
    from tabletop import library

    rate = parse_rate(args.rate if args.rate is not None else "40")
    table = parse_table(args.table) if args.table is not None else None
    params = given = parse_params(args.param)
    if "rate_hz" in params and args.rate is not None and params["rate_hz"] != rate:
        raise BehaveArgumentError(f"--rate {args.rate} and --param rate_hz={params['rate_hz']} "
                                  "disagree; give one")
    if args.rate is not None:
        params.setdefault("rate_hz", rate)
    if args.out is not None:
        output_file(args.out, "--out", BehaveArgumentError,
                    inputs=(args.train, args.train_main, args.train_react, args.input),
                    example="react.csv")
    demo, stored, source = read_demonstration(args)
    params = {"rate_hz": rate, **stored, **params}   # given over stored over the defaults
    # the table the behaviour was made on: a kept one's, or --param's over it (it trained on
    # that table and played on the stored one)
    named = table_from_params(given, params)
    if table is None:
        table = named
    main_rows = None if main_path is None else read_rows(main_path, MAIN_COLUMNS,
                                                         "main path CSV", 1)
    if main_rows is not None:
        check_metres(main_rows[:, 1:3], main_path, "main path")
    check_metres(demo[:, [1, 2]], source, "demonstration's main")
    check_metres(demo[:, [4, 5]], source, "demonstration's reactor")
    folder = Path(source) if args.train is not None and Path(source).is_dir() else None

    def refused(exc: ParameterError) -> BehaveArgumentError:
        """A parameter out of range, named by where it was given: --param, or the folder's
        behavior.yaml at its key."""
        if exc.name is not None and exc.name in parse_params(args.param):
            return BehaveArgumentError(f"--param: {exc}")
        said = folder and library.refused_at_key(folder, stored, exc, given)
        return BehaveArgumentError(said or f"{source}: {exc}")

    try:   # the rate before the rows it asks for (rate_hz=inf was said as the main path's)
        Params(rate_hz=params["rate_hz"]).check()
    except ParameterError as exc:
        raise refused(exc) from None
    if main_rows is not None:
        check_rows_out(main_rows, main_path, float(params["rate_hz"]))
    try:
        behavior = Behavior.train(demo, **params)
    except ParameterError as exc:
        raise refused(exc) from None
    except InputError as exc:   # a need set by --param (a window too long) names it first
        needs = getattr(exc, "params", ())
        named = [f"--param {n}" for n in needs if n in parse_params(args.param)]
        keys = [f"parameters.{n}" for n in needs if folder and n in stored and n not in given]
        where = f"{folder / library.BEHAVIOR_FILE}: {', '.join(keys)}" if keys else source
        raise BehaveArgumentError(f"{', '.join(named + [where])}: {exc}") from None
    if table is None:
        table = behavior.bounds
        if table[2] <= table[0] or table[3] <= table[1]:
            raise BehaveArgumentError(
                f"{source}: the demonstration's positions span no area; give --table W,H")
    warn_still_reactor(demo, source)     # (once trained: an error is its one line)
    warn_degrees(demo, {"main_dir": 3, "react_dir": 6}, source)
    if main_rows is not None:
        warn_degrees(main_rows, {"main_dir": 3}, main_path)
        warn_sparse_times(main_rows[:, 0], "behave", main_path, "the main path's samples")
    return behavior, table, source, main_rows


def check_rows_out(main_rows: np.ndarray, main_path: str, rate_hz: float) -> None:
    """A main path (n, 4) that asks more than MAX_ROWS generation steps at ``rate_hz`` is
    refused naming its file (``main_path``)."""
    rows_out = float(main_rows[-1, 0] - main_rows[0, 0]) * rate_hz
    if rows_out > MAX_ROWS:
        why = sparse_hint(main_rows[:, 0], "; its samples")
        raise BehaveArgumentError(f"{main_path}: the main path spans "
                                  f"{main_rows[-1, 0] - main_rows[0, 0]:g} s, {rows_out:.3g} rows "
                                  f"at {rate_hz:g} Hz; at most {MAX_ROWS:,} rows are generated"
                                  + why)
