"""``tabletop replay``: feed a session recording back through the same engines and view."""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "replay a session recording (JSON Lines) through the engines and the view"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("session", type=Path, metavar="SESSION.jsonl", help="a recording made by run")
    p.add_argument("--fast", action="store_true",
                   help="as fast as possible instead of honouring the recorded times")
    p.add_argument("--headless", action="store_true", help="no window (SDL dummy driver)")
    p.add_argument("--no-view", action="store_true", help="do not draw at all")
    p.add_argument("--out", type=Path, default=None, metavar="FILE",
                   help="record the replayed frames (with the characters made again) to FILE")
    p.add_argument("--verbose", action="store_true", help="log debug messages")


def main(args: argparse.Namespace) -> int:
    from tabletop.app import build_replay, configure_logging, stop_on_signals
    from tabletop.config import validate_config
    from tabletop.recorder import read_frames, read_header

    configure_logging(args.verbose)
    header = read_header(args.session)
    cfg = validate_config(header.get("config") or None, f"{args.session} (recorded config)",
                          args.session.resolve().parent)
    inst = build_replay(cfg, read_frames(args.session), fast=args.fast, headless=args.headless,
                        record_path=args.out, view=not args.no_view)
    with stop_on_signals(inst.loop.stop):
        ticks = inst.loop.run()
    import logging
    logging.getLogger("tabletop").info("replayed %d frames of %s", ticks, args.session)
    return 0
