"""``tabletop replay``: feed a session recording back through the same engines and view.

The recording's header carries the config and the files it refers to: they are unpacked into a
temporary folder and the config is validated there, so a recording replays on any machine and
from any folder. Frames are fed with the times the engines saw live, so the characters are made
again exactly. When the designer studio ran (the header's ``studio``), it runs again: each frame
is given to it as it was live (the control-marker pucks and designer commands it took, kept in
the frame's ``consumed``), so takes, their training and tries are made again frame for frame.
"""

from __future__ import annotations

import argparse
import contextlib
import itertools
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Iterator

from tabletop.cli import EXIT_INTERRUPTED, EXIT_RECORDING_FAILED, one_line
from tabletop.commands import output_file
from tabletop.errors import InputError

if TYPE_CHECKING:
    from tabletop.frames import Frame

HELP = "replay a session recording (JSON Lines) through the engines and the view"


class ReplayError(InputError):
    """A bad ``replay`` argument."""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("session", type=Path, nargs="+", metavar="SESSION.jsonl",
                   help="a recording made by run; several parts of one session (recorder.max_mb) "
                        "are replayed in order, the engines running on from part to part")
    p.add_argument("--fast", action="store_true",
                   help="as fast as possible instead of honouring the recorded times")
    p.add_argument("--headless", action="store_true", help="no window (SDL dummy driver)")
    p.add_argument("--no-view", action="store_true", help="do not draw at all")
    p.add_argument("--out", default=None, metavar="FILE",
                   help="record the replayed frames (with the characters made again) to FILE")
    p.add_argument("--verbose", action="store_true", help="log debug messages")


def session_frames(paths: list[Path], header: dict) -> Iterator[Frame]:
    """The frames of one session's parts in order, at their live times; a file that is not a
    later part of the same session is refused."""
    from tabletop.recorder import SessionError, read_frames, read_header
    last = -math.inf
    for i, path in enumerate(paths):
        if i and read_header(path).get("config") != header.get("config"):
            raise SessionError(f"{path}: line 1: not a part of the session of {paths[0]} "
                               "(its config differs)")
        for n, frame in enumerate(read_frames(path, absolute=True), start=2):
            if frame.t < last:
                raise SessionError(f"{path}: line {n}: goes back in time; give the parts of a "
                                   "session in their order")
            last = frame.t
            yield frame


RECORDINGS = "the recording's "


@contextlib.contextmanager
def recorded_files_named(session: Path, folder: Path) -> Iterator[None]:
    """An InputError about a file the recording carried (unpacked into the temporary ``folder``,
    gone when the command ends) names it as the recording's file, in ``session``: "rec.jsonl:
    the recording's behaviors/x/demonstration.csv: line 1: ...", not the temporary path; one
    about the recording's calibration names ``session`` too."""
    try:
        yield
    except InputError as exc:
        text = str(exc)
        prefixes = {f"{p}{os.sep}" for p in (folder, folder.resolve())}
        if not any(p in text for p in prefixes) and not text.startswith(RECORDINGS):
            raise
        for p in prefixes:
            text = text.replace(p, RECORDINGS)
        if not text.startswith(str(session)):
            text = f"{session}: {text}"
        raise ReplayError(text) from None


def main(args: argparse.Namespace) -> int:
    import logging
    import tempfile

    from tabletop.app import build_replay, configure_logging, stop_on_signals
    from tabletop.bundle import extract
    from tabletop.config import validate_config
    from tabletop.recorder import SessionError, read_header
    from tabletop.parts import resume_parts, with_reloaded

    if args.out is not None:
        args.out = output_file(args.out, "--out", ReplayError, inputs=args.session)
    configure_logging(args.verbose)
    first = args.session[0]
    header = read_header(first)
    part = header.get("part", 1)
    for later in args.session[1:]:  # every part is a recording of the session, in order,
        # checked before anything starts: a part of another session of the same config (a
        # kiosk's next session) is refused, not played on as if the session went on
        later_header = read_header(later)
        n = later_header.get("part", 0)
        # the session first: another session's part 1 is not a part out of order
        session = later_header.get("session")
        if session is not None and header.get("session") is not None \
                and session != header["session"]:
            raise SessionError(f"{later}: line 1: a part of session {one_line(session)[:40]}, "
                               f"not of {first}'s session {one_line(header['session'])[:40]}; "
                               "give the parts of one session")
        if not isinstance(n, int) or not isinstance(part, int) or n <= part:
            raise SessionError(f"{later}: line 1: part {n!r} cannot follow part {part!r}; give "
                               "the parts of a session in their order")
        part = n
    with tempfile.TemporaryDirectory(prefix="tabletop-replay-") as tmp:
        files = header.get("files")
        if files is None:  # version 1: paths as they were on the recording machine
            base = first.resolve().parent
        else:
            base = Path(tmp)
            try:
                extract(files, base)
            except InputError as exc:
                raise SessionError(f"{first}: line 1: {exc}") from None
        if not header.get("config"):
            raise SessionError(f"{first}: line 1: the header holds no config to replay with")
        with recorded_files_named(first, Path(tmp)):
            # (a kiosk that started characters without actions it could not read: so too)
            cfg = validate_config(header["config"], f"{first} (recorded config)", base,
                                  start_without=bool(header.get("started_without")))
            frames = session_frames(args.session, header)
            start = next(frames, None)  # (a bad first frame is said before anything is written)
            if start is None:
                raise SessionError(f"{first}: no complete frame after the header line: nothing "
                                   "to replay")
            # a later part replayed first: what the session had reloaded when it began
            try:
                start = with_reloaded(start, header.get("reloaded"))
            except (TypeError, ValueError) as exc:
                raise SessionError(f"{first}: line 1: reloaded: {exc}") from None
            frames = itertools.chain([start], frames)
            studio = header.get("studio")
            if isinstance(studio, dict):
                from tabletop.studio.build import studio_input
                frames = map(studio_input, frames)
            inst = build_replay(cfg, frames, fast=args.fast, headless=args.headless,
                                record_path=args.out, view=not args.no_view,
                                header={k: v for k, v in header.items()
                                        if k != "reloaded"})
            try:     # a later part replayed first: its engines as they were when it began
                resume_parts(inst.engines, header.get("performers") or {})
            except (KeyError, TypeError, ValueError) as exc:
                raise SessionError(f"{first}: line 1: performers: {exc}") from None
            from tabletop.studio.reloader import RecordedReloads
            inst.loop.filters.insert(0, RecordedReloads(inst.engines))  # hot reloads, as live
            if isinstance(studio, dict):
                from tabletop.studio.build import attach_studio
                attach_studio(inst, cfg, base, all_engines=bool(studio.get("all")), replay=True)
        with stop_on_signals(inst.loop.stop) as received:
            ticks = inst.loop.run()
    names = ", ".join(map(str, args.session))
    if received:   # a script must not take a replay cut short (and its --out) for a whole one
        logging.getLogger("tabletop").warning("replay interrupted by %s after %d frames of %s",
                                              received[0], ticks, names)
        return EXIT_INTERRUPTED
    logging.getLogger("tabletop").info("replayed %d frames of %s", ticks, names)
    recorder = inst.recorder   # an --out cut short (a full disk) is not the whole replay
    if recorder is not None and recorder.incomplete:
        logging.getLogger("tabletop").error("--out %s is incomplete: %s", args.out,
                                            recorder.incomplete)
        return EXIT_RECORDING_FAILED
    return 0
