"""``tabletop replay``: feed a session recording back through the same engines and view.

The recording's header carries the config and the files it refers to: they are unpacked into a
temporary folder and the config is validated there, so a recording replays on any machine and
from any folder. Frames are fed with the times the engines saw live, so the characters are made
again exactly.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tabletop.commands import output_file
from tabletop.frames import InputError

HELP = "replay a session recording (JSON Lines) through the engines and the view"


class ReplayError(InputError):
    """A bad ``replay`` argument."""


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
    import logging
    import tempfile

    from tabletop.app import build_replay, configure_logging, stop_on_signals
    from tabletop.bundle import extract
    from tabletop.config import validate_config
    from tabletop.recorder import SessionError, read_frames, read_header

    if args.out is not None:
        output_file(args.out, "--out", ReplayError)
    configure_logging(args.verbose)
    header = read_header(args.session)
    with tempfile.TemporaryDirectory(prefix="tabletop-replay-") as tmp:
        files = header.get("files")
        if files is None:  # version 1: paths as they were on the recording machine
            base = args.session.resolve().parent
        else:
            base = Path(tmp)
            try:
                extract(files, base)
            except InputError as exc:
                raise SessionError(f"{args.session}: line 1: {exc}") from None
        if not header.get("config"):
            raise SessionError(f"{args.session}: line 1: the header holds no config to replay "
                               "with")
        cfg = validate_config(header["config"],
                              f"{args.session} (recorded config)", base)
        inst = build_replay(cfg, read_frames(args.session, absolute=True), fast=args.fast,
                            headless=args.headless, record_path=args.out, view=not args.no_view,
                            header=header)
        with stop_on_signals(inst.loop.stop):
            ticks = inst.loop.run()
    logging.getLogger("tabletop").info("replayed %d frames of %s", ticks, args.session)
    return 0
