"""``tabletop status HOST:PORT``: print the heartbeats of every table sending to HOST:PORT."""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import time
from typing import Any, Callable

from tabletop.cli import one_line

HELP = "listen for the tables' heartbeats on HOST:PORT and print one line per heartbeat"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("address", metavar="HOST:PORT",
                   help="where to listen, e.g. 0.0.0.0:9000 or [::]:9000 (the tables' "
                        "kiosk.heartbeat)")
    p.add_argument("--seconds", default=None, metavar="S",
                   help="stop after S seconds (default: until Ctrl-C)")
    p.add_argument("--json", action="store_true", help="print each table's status JSON instead")


def parse_address(text: str) -> tuple[str, int]:
    """``HOST:PORT`` -> (host, port); an IPv6 address in brackets (``[::1]:9000``)."""
    from tabletop.errors import InputError
    from tabletop.resolve import host_port
    try:
        return host_port(text)
    except ValueError as exc:
        raise InputError(f"address {exc}") from None


# the ranges of a heartbeat's numbers a table can send: an uptime of up to a century (s); an
# fps up to 1.5 x the highest loop.rate_hz (1000; a window's measure reads a little over the
# rate); unhealthy sources a whole count, up to far more sources than any config holds.
# Beyond them (fps 3e38, -2 or 1.5 unhealthy sources) it is another program's, not printed.
HEARTBEAT_RANGES = {"uptime": (0.0, 100 * 365.25 * 86400), "fps": (0.0, 1500.0),
                    "unhealthy sources": (0, 10_000)}


def check_heartbeat(values: tuple) -> str:
    """What is wrong with a heartbeat's OSC arguments (name, uptime s, fps, unhealthy sources,
    status JSON), naming the field, or "" when they are what a table sends."""
    if len(values) != 5:
        return f"{len(values)} values, expected 5"
    name, uptime, fps, unhealthy, status = values
    for what, v in (("uptime", uptime), ("fps", fps), ("unhealthy sources", unhealthy)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            return f"{what} {str(v)[:40]!r} is not a number"
        lo, hi = HEARTBEAT_RANGES[what]
        if isinstance(lo, int) and not isinstance(v, int):
            return f"{what} {v:g} is not a whole number"
        if not lo <= v <= hi:
            return f"{what} {v:g} is out of range {lo:g}..{hi:g}"
    if not isinstance(name, str) or not isinstance(status, str):
        return "name and status must be strings"
    return ""


def status_object(status: str) -> dict | None:
    """The status JSON as a dict (strict JSON: no NaN or Infinity), None when it is not one."""
    def refuse(constant: str) -> None:
        raise ValueError(constant)
    try:
        st = json.loads(status, parse_constant=refuse)
    except (ValueError, RecursionError):
        return None
    return st if isinstance(st, dict) else None


SHOWN = 64   # characters of a heartbeat's name or mode printed (a 5000-character name, sent by
# anything on the network, filled the terminal)


def shortened(value: object) -> str:
    """``value`` on one line, cut to SHOWN characters (an ellipsis says so)."""
    text = one_line(value)
    return text if len(text) <= SHOWN else text[:SHOWN - 3] + "..."


def format_heartbeat(sender: str, name: str, uptime: float, fps: float, unhealthy: int,
                     status: str) -> str:
    """One line, in columns: name, sender, uptime (s), fps (frames/s), unhealthy sources, mode
    and any problem (what the sender wrote is put on one line field by field, the columns kept)."""
    st = status_object(status) or {}
    mode = shortened(st.get("mode", "?"))
    extra = ""
    if st.get("config_error"):
        extra += "  config refused"
    if st.get("restarts"):
        extra += f"  restarts {shortened(st['restarts'])}"
    return (f"{shortened(name):<16} {sender:<21} up {uptime:9.1f} s  {fps:5.1f} fps  "
            f"{unhealthy} unhealthy  {mode}{extra}")


def waited(seconds: float) -> str:
    """The seconds waited, as the no-heartbeat line gives them: tenths below 10 s (a short
    ``--seconds`` reads "0.3", not "0"), whole seconds from 10 on; decided on the rounded
    figure, so 9.97 reads "10", as 10.0 does, not "10.0"."""
    tenths = round(seconds, 1)
    return f"{tenths:.1f}" if tenths < 10 else f"{seconds:.0f}"


def listener(address: tuple[str, int], on_heartbeat: Callable[..., None]) -> Any:
    """A UDP server on ``address`` handing each ``/tabletop/heartbeat`` message of a datagram
    to ``on_heartbeat(client, address, *values)``, decoded by :mod:`tracking.osc_codec` as the
    ``osc`` source decodes: a malformed datagram raises its ``OscError`` to the server's
    ``handle_error`` (one line naming the sender). python-osc's own dispatch is not used: it
    sleeps until a bundle's timetag (a stray bundle tagged 2036 would hold the command past
    ``--seconds`` for good), reads at most 8192 bytes of a datagram (a 12 kB status, a table
    with many sources' messages, would be no heartbeat at all) and tells what it skips through
    the root logger ("WARNING:root:Unhandled parameter type"), naming no sender."""
    from pythonosc.dispatcher import Dispatcher
    from pythonosc.osc_server import BlockingOSCUDPServer

    from tabletop.kiosk.health import HEARTBEAT_ADDRESS
    from tracking.osc_codec import decode_packet

    class Listener(BlockingOSCUDPServer):
        max_packet_size = 65536   # a UDP datagram's largest payload, whole

        def verify_request(self, request: Any, client_address: Any) -> bool:
            return True   # (decode_packet names what is wrong with any datagram)

        def finish_request(self, request: Any, client_address: Any) -> None:
            for where, values in decode_packet(request[0]).messages:
                if where == HEARTBEAT_ADDRESS:
                    on_heartbeat(client_address, where, *values)

    return Listener(address, Dispatcher())


#: exit status when no table's heartbeat came (a monitoring script's ``status ... || alert``)
EXIT_NO_TABLE = 1


def main(args: argparse.Namespace) -> int:
    """Print every table's heartbeat until ``--seconds`` or Ctrl-C; 0 when a table's heartbeat
    came, EXIT_NO_TABLE when none did (only silence or bad heartbeats)."""
    import threading

    from tabletop.commands import number_in_range
    from tabletop.commands.run import MAX_SECONDS
    from tabletop.errors import InputError
    from tabletop.resolve import shown_host_port
    from tracking.badinput import LogGaps
    from tracking.osc_codec import OscError
    from tracking.osc_input import plain_address

    def sender(client: Any) -> str:
        """A table's address as HOST:PORT, an IPv4 table as its IPv4 address also when the
        listener takes every IPv6 and IPv4 interface ([::]:9000 reports [::ffff:A.B.C.D]:P)."""
        return shown_host_port(plain_address(client[0]), client[1])

    host, port = parse_address(args.address)
    seconds = None if args.seconds is None else number_in_range(
        args.seconds, "--seconds", "seconds", 0.001, MAX_SECONDS)

    came, shown = [], []

    def on_heartbeat(client: tuple[Any, ...], address: str, *values: Any) -> None:
        came.append(True)
        wrong = check_heartbeat(values)
        st = status_object(values[4]) if not wrong and args.json else None
        if args.json and not wrong and st is None:   # --json prints JSON objects only
            wrong = "status is not a JSON object"
        if wrong:  # another program on the port: said in one line, listening goes on
            say(client, f"bad heartbeat {wrong}", f"{sender(client)}: bad heartbeat ({wrong})")
            return
        name, uptime, fps, unhealthy, status = values
        shown.append(True)   # before its line: a Ctrl-C just after the line exited 1
        if args.json:  # one line of strict JSON, whatever white space the sender used
            print(json.dumps(st, separators=(",", ":")), flush=True)
        else:
            print(format_heartbeat(sender(client), str(name), float(uptime),
                                   float(fps), int(unhealthy), str(status)), flush=True)

    try:
        server = listener((host, port), on_heartbeat)
    except OSError as exc:
        raise InputError(f"cannot listen on {shown_host_port(host, port)}: "
                         f"{exc.strerror or exc}") from None

    gaps = LogGaps()              # refused packets: when to say them,
    unsaid: dict[str, int] = {}   # and how many were not said, by sender and kind
    forgotten = 0                 # unsaid counts of kinds dropped from ``unsaid`` (bounded)

    def handle_error(_request: Any, client: Any) -> None:
        """In place of socketserver's own, which prints a handler's exception with its
        traceback and serves on (a reader gone, ``status ... | head -1``, would give one
        traceback a heartbeat, for good): a closed output leaves serve_forever (the CLI's
        quiet 141); a packet the OSC decoder refuses (a stray sender's: a string that is no
        UTF-8, an argument cut short, no OSC at all) is one line, and the heartbeats go on
        being shown."""
        exc = sys.exc_info()[1]
        if isinstance(exc, BrokenPipeError):
            raise exc
        what = one_line(exc) if isinstance(exc, OscError) else \
            f"{type(exc).__name__}: {one_line(exc)}"
        say(client, what, f"tabletop status: a packet from {sender(client)} refused: {what}")

    def say(client: Any, what: str, line: str) -> None:
        """``line`` on stderr at once, then while the same sender keeps sending the same kind
        ``what`` (numbers aside), after 10 s, 20 s, ... (LogGaps) with the count left unsaid: a
        program sending no OSC to the port at 60 Hz filled the terminal with 60 lines a second,
        and so did one sending heartbeats of another form (300 lines in 1.5 s)."""
        nonlocal gaps, forgotten
        key = f"{client[0]} {re.sub(r'[0-9]+', 'N', what)}"
        if key not in unsaid and len(unsaid) >= 1024:   # (from the network: bounded)
            gaps = LogGaps()
            forgotten += sum(unsaid.values())
            unsaid.clear()
        if not gaps.due(key, time.monotonic()):
            unsaid[key] = unsaid.get(key, 0) + 1
            return
        more, unsaid[key] = unsaid.get(key, 0), 0
        print(line + (f" ({more} more like it since the last line)" if more else ""),
              file=sys.stderr, flush=True)

    server.handle_error = handle_error  # type: ignore[method-assign]
    timer = None
    if seconds is not None:   # a daemon, cancelled on Ctrl-C: otherwise it keeps the process
        # for the rest of --seconds after a Ctrl-C, and a second Ctrl-C prints a traceback
        timer = threading.Timer(seconds, server.shutdown)
        timer.daemon = True
        timer.start()
    start = time.monotonic()
    try:
        server.serve_forever(poll_interval=0.1)
    except KeyboardInterrupt:
        pass
    finally:
        if timer is not None:
            timer.cancel()
        server.server_close()
    held = forgotten + sum(unsaid.values())
    if held:   # what was held back since each kind's last line: its count, not a silence
        print(f"tabletop status: {held} more like the lines above not said (the same fault "
              "from the same sender is said once, then after 10 s, 20 s, ...)", file=sys.stderr)
    if not came:   # silence alone does not tell a quiet gallery from a wrong address
        print(f"tabletop status: no heartbeat came to {shown_host_port(host, port)} in "
              f"{waited(time.monotonic() - start)} s (a table in kiosk mode sends one every "
              "kiosk.heartbeat.every_s to kiosk.heartbeat.host:port)", file=sys.stderr)
    return 0 if shown else EXIT_NO_TABLE
