"""Source ``serial``: the line protocol of DESIGN.md from a serial device or any pyserial URL.

``port`` is a device (``/dev/ttyACM0``, ``COM3``) or a pyserial URL (``loop://``,
``socket://HOST:PORT``, ``rfc2217://...``); a device that is missing at start-up or vanishes
later is reopened with a growing back-off while the installation keeps running. See
:mod:`tracking.serial_input` for the lines and how bad ones are counted.
"""

from __future__ import annotations

import os
import re
import stat
from urllib.parse import urlsplit
from typing import Any

from tabletop.registry import BuildContext
from tabletop.resolve import host_port
from tabletop.schema import Context, Number, Optional_, Record, Str, shown
from tracking.serial_input import SerialInput


NETWORK_URLS = ("socket", "rfc2217")   # pyserial URL protocols of a HOST:PORT
WINDOWS_PORT = re.compile(r"(?i)COM\d+\Z")    # COM3: a port name, not a relative path


class Port(Str):
    """A serial device (``/dev/ttyACM0``, ``COM3``: it may be plugged in later; a relative path
    is relative to the config file's folder, as every path of the config) or a pyserial URL.
    Refused at start, as they can never open: an empty name, a URL of a protocol pyserial
    does not have, a ``socket://`` or ``rfc2217://`` URL whose HOST:PORT is malformed, and a
    path that exists but is a file or a folder (each was retried for ever)."""

    def __init__(self) -> None:
        super().__init__(doc="a serial device such as /dev/ttyACM0, or a pyserial URL such as "
                             "loop:// or socket://HOST:PORT")

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        value = super().validate(value, path, ctx)
        if not value.strip():
            raise ctx.error(path, f"expected {self.doc}, got {shown(value)}")
        if "://" in value:
            protocol = value.split("://", 1)[0]
            known = url_protocols()
            if protocol not in known:
                raise ctx.error(path, f"{shown(value)}: pyserial has no URL protocol "
                                      f"{protocol!r} (known: {', '.join(known)})")
            if protocol in NETWORK_URLS:   # socket://[::1]:7000; "socket://::1:7000" was
                # retried for ever with pyserial's "Port could not be cast to integer value"
                try:   # pyserial reads the URL with urlsplit: a path or fragment may follow
                    where = urlsplit(value).netloc
                except ValueError:   # "socket://[host]:7": told below as any bad HOST:PORT
                    where = value.split("://", 1)[1]
                try:
                    host_port(where)
                except ValueError as exc:
                    raise ctx.error(path, f"{protocol}:// URL {exc}") from None
            return value
        if not WINDOWS_PORT.match(value):
            # relative to the config file, as every path of the config is, so "port: board"
            # (a link beside the config) opens it whatever folder a kiosk's service starts in
            value = str(ctx.base / os.path.expanduser(value))   # (an absolute one stays)
        try:
            mode = os.stat(value).st_mode
        except (OSError, ValueError):   # not there (yet), or not a path at all
            return value
        if not stat.S_ISCHR(mode):
            what = "a folder" if stat.S_ISDIR(mode) else "a file"
            raise ctx.error(path, f"{shown(value, 200)} is {what}, not a serial device (such as "
                                  "/dev/ttyACM0) or a pyserial URL")
        return value


def url_protocols() -> list[str]:
    """The URL protocols pyserial's ``serial_for_url`` opens (``loop``, ``socket``, ...)."""
    import pkgutil

    import serial.urlhandler
    return sorted(m.name.removeprefix("protocol_") for m in
                  pkgutil.iter_modules(serial.urlhandler.__path__)
                  if m.name.startswith("protocol_"))


SCHEMA = Record({
    "port": Port(),
    "baudrate": Number(115200, integer=True, unit="bits per second",
                       lo=50, hi=12_000_000, doc="bits per second"),
    "timeout_s": Number(0.5, lo=0.01, hi=600.0,
                        doc="a puck, touch or stream not repeated this long leaves the bus"),
    "retry_max_s": Number(8.0, lo=0.1, hi=600.0, doc="longest wait between reconnections"),
    "stall_s": Optional_(Number(lo=0.1, hi=3600.0),
                         doc="health turns bad when the open port delivered no valid line (a "
                             "command, comment or blank line) this long; null: never (a "
                             "device may stay silent while the table is empty)"),
})


def build(options: dict, ctx: BuildContext) -> SerialInput:
    return SerialInput(options["name"], options["port"], options["baudrate"],
                       options["timeout_s"], retry_max_s=options["retry_max_s"],
                       stall_s=options["stall_s"])
