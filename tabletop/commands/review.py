"""``tabletop review SESSION_LOG``: a contact sheet of a studio session's tries."""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "draw a contact sheet (PNG) of a designer studio session log"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("session", type=Path, metavar="SESSION_LOG", help="a studio session .jsonl")
    p.add_argument("--out", type=Path, default=None, metavar="SHEET.png",
                   help="PNG to write (default: SESSION_LOG with -sheet.png)")
    p.add_argument("--columns", default="3", metavar="N",
                   help="sheets per row (default 3)")


def main(args: argparse.Namespace) -> int:
    from tabletop.commands import number_in_range, png_output
    from tabletop.errors import InputError
    from tabletop.studio.review import contact_sheet
    # (a text, as every command's numbers: argparse's int said "invalid int value: ''")
    columns = int(number_in_range(args.columns, "--columns", "sheets per row", 1, 1e6,
                                  integer=True))
    if args.session.is_dir():     # also '' (the current folder): it has no name to derive --out
        logs = sorted(args.session.glob("session-*.jsonl"))   # (a studio folder: its latest)
        raise InputError(f"{args.session}: is a folder, expected a studio session log (.jsonl)"
                         + (f"; its latest is {logs[-1]}" if logs else ""))
    out = args.out or args.session.with_name(args.session.stem + "-sheet.png")
    png_output(out, "--out", InputError, inputs=(args.session,), example="sheet.png")
    print(f"{out}: {contact_sheet(args.session, out, columns)}")
    return 0
