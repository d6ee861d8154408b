"""``tabletop run``: the installation, from a config file."""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "run the installation (synthetic camera and headless view where there is no camera or display)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--config", default="config.yaml", help="config file (default: config.yaml)")
    p.add_argument("--headless", action="store_true", help="no window (SDL dummy driver)")
    p.add_argument("--seconds", type=float, default=None, metavar="S",
                   help="stop after S seconds (default: run until Esc, Ctrl-C or SIGTERM)")
    p.add_argument("--record", type=Path, default=None, metavar="FILE",
                   help="record the session to FILE (JSON Lines), whatever the config says")
    p.add_argument("--verbose", action="store_true", help="log debug messages")


def main(args: argparse.Namespace) -> int:
    from tabletop.app import build_live, configure_logging, stop_on_signals
    from tabletop.config import load_config
    from tabletop.frames import InputError

    if args.seconds is not None and not args.seconds > 0:
        raise InputError(f"--seconds must be a positive number of seconds, got {args.seconds}")
    configure_logging(args.verbose)
    cfg = load_config(args.config)
    inst = build_live(cfg, headless=args.headless, record_path=args.record)
    with stop_on_signals(inst.loop.stop):
        ticks = inst.loop.run(seconds=args.seconds)
    st = inst.loop.stats
    summary = st.summary_ms()
    import logging
    logging.getLogger("tabletop").info(
        "ran %d ticks at %.1f fps; capture-to-render %.1f ms median, %.1f ms p99", ticks,
        st.fps(), *(summary.get("capture_age", (float("nan"),) * 2)))
    return 0
