"""``tabletop run``: the installation, from a config file."""

from __future__ import annotations

import argparse
import threading
from pathlib import Path

MAX_SECONDS = 10 * 365 * 86_400.0  # ten years: a longer run is a typing mistake

HELP = "run the installation (synthetic camera and headless view where there is no camera or display)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--config", default="config.yaml", help="config file (default: config.yaml)")
    p.add_argument("--headless", action="store_true", help="no window (SDL dummy driver)")
    p.add_argument("--seconds", default=None, metavar="S",
                   help="stop after S seconds (default: run until Esc, Ctrl-C, SIGTERM or SIGHUP)")
    p.add_argument("--record", type=Path, default=None, metavar="FILE",
                   help="record the session to FILE (JSON Lines), whatever the config says")
    p.add_argument("--verbose", action="store_true", help="log debug messages")


EXIT_RECORDING_FAILED = 3


def main(args: argparse.Namespace) -> int:
    from tabletop.app import build_live, configure_logging, stop_on_signals
    from tabletop.commands import number_in_range, output_file
    from tabletop.config import load_config

    seconds = None if args.seconds is None else number_in_range(
        args.seconds, "--seconds", "seconds", 1e-3, MAX_SECONDS)
    if args.record is not None:
        output_file(args.record, "--record")
    configure_logging(args.verbose)
    cfg = load_config(args.config)
    stop = threading.Event()
    with stop_on_signals(stop):  # a signal while building still ends the run cleanly
        inst = build_live(cfg, headless=args.headless, record_path=args.record, stop=stop)
        ticks = inst.loop.run(seconds=seconds)
    st = inst.loop.stats
    summary = st.summary_ms()
    import logging
    logging.getLogger("tabletop").info(
        "ran %d ticks at %.1f fps; capture-to-render %.1f ms median, %.1f ms p99", ticks,
        st.fps(), *(summary.get("capture_age", (float("nan"),) * 2)))
    recorder = inst.recorder
    if recorder is not None and recorder.failed:
        logging.getLogger("tabletop").error("the recording failed: %s", recorder.failed)
        return EXIT_RECORDING_FAILED
    return 0
