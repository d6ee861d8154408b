"""``tabletop run``: the installation, from a config file."""

from __future__ import annotations

import argparse
from pathlib import Path

from tabletop.cli import EXIT_RECORDING_FAILED

MAX_SECONDS = 10 * 365 * 86_400.0  # ten years: a longer run is a typing mistake

HELP = ("run the installation (synthetic camera and headless view where there is no camera or "
        "display)")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--config", default="config.yaml", help="config file (default: config.yaml)")
    p.add_argument("--headless", action="store_true", help="no window (SDL dummy driver)")
    p.add_argument("--seconds", default=None, metavar="S",
                   help="stop after S seconds (default: run until Esc, Ctrl-C, SIGTERM or SIGHUP)")
    p.add_argument("--record", default=None, metavar="FILE",
                   help="record the session to FILE (JSON Lines), whatever the config says")
    p.add_argument("--verbose", action="store_true", help="log debug messages")
    p.add_argument("--kiosk", action="store_true",
                   help="gallery kiosk: fullscreen, no cursor, overlay only with the service key, "
                        "attract mode, status and heartbeat, restarted by a supervisor")
    p.add_argument("--no-supervisor", action="store_true",
                   help="with --kiosk (or kiosk.enabled): run the loop in this process "
                        "(e.g. when systemd restarts it)")
    p.add_argument("--studio", action="store_true",
                   help="designer studio: record, train, try, keep and manage the library")


def main(args: argparse.Namespace) -> int:
    from tabletop.commands import number_in_range, output_file
    # the arguments first, before the installation's modules (and their compiled kernels) load
    seconds = None if args.seconds is None else number_in_range(
        args.seconds, "--seconds", "seconds", 1e-3, MAX_SECONDS)
    if args.record is not None:
        args.record = output_file(args.record, "--record")
    from tabletop.kiosk import spare
    prepared, changed = None, None
    if spare.is_spare():                 # the supervisor's warm spare: ready before its go
        go, prepared, changed = spare.wait_for_go(Path(args.config))
        if not go:
            return 0
    from tabletop.app import configure_logging, stop_on_signals
    from tabletop.kiosk import last_good
    from tabletop.kiosk.supervised import follow_supervisor, supervised

    configure_logging(args.verbose)
    # a kiosk whose config is refused at its start runs the last one that ran (last_good)
    cfg, refused = ((prepared.cfg, None) if prepared is not None
                    else last_good.load(Path(args.config), args.kiosk))
    kiosk = args.kiosk or cfg["kiosk"]["enabled"]
    if args.no_supervisor and not kiosk:   # it says where a kiosk's loop runs, nothing else
        from tabletop.errors import InputError
        raise InputError(f"--no-supervisor is for a kiosk: add --kiosk (or kiosk.enabled: "
                         f"true in {args.config})")
    if kiosk:   # no kiosk file may write over the config, nor two of them be one, nor the
        # heartbeat go to the installation's own osc source
        from tabletop.config_ports import check_heartbeat
        from tabletop.kiosk.settings import check_files
        check_files(cfg)
        check_heartbeat(cfg)
    lock_fd = None
    if kiosk and not supervised():
        # one kiosk per folder, before anything of the folder is touched (the supervisor's
        # installation and spares hold this lock with it: they are never refused)
        from tabletop.kiosk.lock import lock_folder
        lock_fd = lock_folder(Path(args.config).resolve().parent)
    if kiosk and not args.no_supervisor and not supervised():
        # the supervisor never loads the installation's modules: it starts the installation
        # sooner at boot and holds less memory for weeks (see bench/cold_start.py)
        from tabletop.kiosk.supervisor import supervise
        return supervise(Path(args.config), cfg, _argv(args), seconds, lock_fd)
    from tabletop.kiosk.runner import Runner
    runner = Runner(Path(args.config), cfg, headless=args.headless, record_path=args.record,
                    kiosk=kiosk, studio=args.studio, prepared=prepared, config_error=refused,
                    strict=not (kiosk or supervised()))   # a kiosk's start may be a restart
    # (by its supervisor, or by systemd with --no-supervisor): it runs on
    spare.say_changed(changed, Path(args.config))   # (into the kiosk's log, set up by now)
    if supervised():
        follow_supervisor(runner.stop)   # a supervisor killed outright ends its installation
    with stop_on_signals(runner.stop):  # a signal while building still ends the run cleanly
        runner.run(seconds=seconds)
    inst = runner.inst
    st = inst.loop.stats
    summary = st.summary_ms()
    import logging
    age = summary.get("capture_age")   # none while no source delivered (a camera unplugged)
    latency = "%.1f ms median, %.1f ms p99" % age if age else "none (nothing was captured)"
    logging.getLogger("tabletop").info(
        "ran %d ticks in %.2f s at %s; capture-to-render %s", runner.ticks, runner.run_s,
        rate_words(runner.ticks, runner.run_s, st.fps(), len(st.tick_times)), latency)
    recorder = inst.recorder
    if recorder is not None and recorder.incomplete:
        logging.getLogger("tabletop").error("the recording failed: %s", recorder.incomplete)
        return EXIT_RECORDING_FAILED
    if runner.recording_failures:   # an installation's before an applied config edit
        logging.getLogger("tabletop").error(
            "the recording failed before a config edit was applied: %s",
            runner.recording_failures[-1])
        return EXIT_RECORDING_FAILED
    return 0


def _argv(args: argparse.Namespace) -> list[str]:
    """The arguments of this run, for the supervised child (``--seconds`` is the supervisor's:
    it stops the kiosk that long after it was first ready, restarts included)."""
    out = ["--config", str(args.config)]
    if args.headless:
        out.append("--headless")
    if args.record is not None:
        out += ["--record", str(args.record)]
    if args.verbose:
        out.append("--verbose")
    if args.studio:
        out.append("--studio")
    return out + ["--kiosk"]


def rate_words(ticks: int, run_s: float, window_fps: float | None, window_ticks: int) -> str:
    """The last line's rate: the run's own average (``ticks`` over ``run_s`` seconds, as the
    line's "ran N ticks in T s" reads), and the rate over the loop's kept window
    (:meth:`~tabletop.loop_stats.LoopStats.fps`, the overlay's) beside it where the two differ
    by more than 2%: a kiosk's line said "ran 755 ticks in 12.34 s at 65.6 fps", the window's
    rate after a catch-up. A run shorter than the window has no window rate (None)."""
    average = ticks / run_s if run_s > 0 else 0.0
    said = "%.1f fps" % average
    if window_fps is not None and abs(window_fps - average) > 0.02 * max(average, 1e-9):
        said += " (%.1f fps over the last %d ticks)" % (window_fps, window_ticks)
    return said
