"""Source ``serial``: the line protocol of DESIGN.md from a serial device or any pyserial URL.

``port`` is a device (``/dev/ttyACM0``, ``COM3``) or a pyserial URL (``loop://``,
``socket://HOST:PORT``, ``rfc2217://...``); a device that is missing at start-up or vanishes
later is reopened with a growing back-off while the installation keeps running. See
:mod:`tracking.serial_input` for the lines and how bad ones are counted.
"""

from __future__ import annotations

from tabletop.registry import BuildContext
from tabletop.schema import Number, Record, Str
from tracking.serial_input import SerialInput

SCHEMA = Record({
    "port": Str(doc="a serial device such as /dev/ttyACM0, or a pyserial URL such as loop:// "
                    "or socket://HOST:PORT"),
    "baudrate": Number(115200, integer=True, lo=50, hi=12_000_000, doc="bits per second"),
    "timeout_s": Number(0.5, lo=0.01, hi=600.0,
                        doc="a puck, touch or stream not repeated this long leaves the bus"),
    "retry_max_s": Number(8.0, lo=0.1, hi=600.0, doc="longest wait between reconnections"),
})


def build(options: dict, ctx: BuildContext) -> SerialInput:
    return SerialInput(options["name"], options["port"], options["baudrate"],
                       options["timeout_s"], retry_max_s=options["retry_max_s"])
