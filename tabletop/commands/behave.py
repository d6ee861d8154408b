"""``tabletop behave``: train a Puppet Master behaviour and generate a reactor for a main path."""

from __future__ import annotations

import argparse
import math

from tabletop.commands import number_in_range
from tabletop.frames import InputError

HELP = ("train a reactive behaviour from a demonstration CSV and generate the reactor's motion "
        "for a main character's path, causally, at the generation rate")

DEMO_COLUMNS = ("t", "main_x", "main_y", "main_dir", "react_x", "react_y", "react_dir")
MAIN_COLUMNS = ("t", "main_x", "main_y", "main_dir")
OUT_COLUMNS = ("t", "react_x", "react_y", "react_dir")


class BehaveArgumentError(InputError):
    """A bad ``behave`` argument."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--train", required=True, metavar="DEMO.csv",
                        help="demonstration: t,main_x,main_y,main_dir,react_x,react_y,react_dir "
                             "(seconds, table metres, radians), any sampling rate")
    parser.add_argument("--input", required=True, metavar="MAIN.csv",
                        help="main character's path: t,main_x,main_y,main_dir, any rate")
    parser.add_argument("--out", required=True, metavar="REACT.csv",
                        help="output: t,react_x,react_y,react_dir, one row per generation step")
    parser.add_argument("--rate", default="40", metavar="HZ",
                        help="generation rate in Hz (default 40)")
    parser.add_argument("--table", default=None, metavar="W,H",
                        help="table size in metres from the origin; the reactor stays on it "
                             "(default: the bounds of the demonstration's positions)")


MAX_RATE_HZ = 1000.0   # generation steps per second (the behaviours are made at 40)
MAX_DEMO_S = 3600.0    # seconds of demonstration (the paper's are 10 to 80 s)
MAX_ROWS = 2_000_000   # output rows (14 h of main path at 40 Hz)
TABLE_M = (0.05, 20.0)  # metres: a table side, as config.yaml's table section


def parse_rate(text: str) -> float:
    """A rate in Hz from 1 to MAX_RATE_HZ."""
    return number_in_range(text, "--rate", "Hz", 1.0, MAX_RATE_HZ, BehaveArgumentError)


def parse_table(text: str) -> tuple[float, float, float, float]:
    """``W,H`` in metres -> (0, 0, W, H)."""
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise ValueError
        w, h = float(parts[0]), float(parts[1])
    except ValueError:
        raise BehaveArgumentError(f"--table {text!r} must be W,H in metres, e.g. 1.6,1.0") from None
    lo, hi = TABLE_M
    if not (math.isfinite(w) and math.isfinite(h)) or not (lo <= w <= hi and lo <= h <= hi):
        raise BehaveArgumentError(f"--table {text!r}: width and height must be metres from "
                                  f"{lo:g} to {hi:g}")
    return 0.0, 0.0, w, h


def main(args: argparse.Namespace) -> int:
    from behaviors.puppet_master.engine import Behavior, Reactor
    from tabletop.files import check_increasing, read_csv_lines, write_csv

    rate = parse_rate(args.rate)
    table = parse_table(args.table) if args.table is not None else None
    header, demo, lines = read_csv_lines(args.train, DEMO_COLUMNS, what="demonstration CSV",
                                         min_rows=2)
    demo = demo[:, [header.index(c) for c in DEMO_COLUMNS]]
    check_increasing(demo[:, 0], args.train, lines=lines)
    header, main_rows, lines = read_csv_lines(args.input, MAIN_COLUMNS, what="main path CSV",
                                              min_rows=1)
    main_rows = main_rows[:, [header.index(c) for c in MAIN_COLUMNS]]
    check_increasing(main_rows[:, 0], args.input, lines=lines)
    span = float(demo[-1, 0] - demo[0, 0])
    if span > MAX_DEMO_S:
        raise BehaveArgumentError(f"{args.train}: the demonstration spans {span:g} s; at most "
                                  f"{MAX_DEMO_S:g} s can be trained")
    rows_out = float(main_rows[-1, 0] - main_rows[0, 0]) * rate
    if rows_out > MAX_ROWS:
        raise BehaveArgumentError(f"{args.input}: the main path spans "
                                  f"{main_rows[-1, 0] - main_rows[0, 0]:g} s, {rows_out:.3g} rows "
                                  f"at {rate:g} Hz; at most {MAX_ROWS:,} rows are generated")
    try:
        behavior = Behavior.train(demo, rate_hz=rate)
    except InputError as exc:
        raise BehaveArgumentError(f"{args.train}: {exc}") from None
    if table is None:
        table = behavior.bounds
        if table[2] <= table[0] or table[3] <= table[1]:
            raise BehaveArgumentError(
                f"{args.train}: the demonstration's positions span no area; give --table W,H")
    reactor = Reactor(behavior, table, max_backlog=None)
    rows: list[tuple[float, float, float, float]] = []
    for t, x, y, d in main_rows:
        rows.extend(reactor.advance(float(t), float(x), float(y), float(d)))
    write_csv(args.out, OUT_COLUMNS, rows)
    return 0
