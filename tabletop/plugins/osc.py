"""Source ``osc``: TUIO 1.1 pucks and touches and ``/mocap/NAME`` streams over UDP.

Listens on ``host`` (loopback by default: other machines cannot reach it until a technician
names an interface address, or 0.0.0.0 for all) and ``port``; ``allow`` lists the sender
addresses accepted (empty: any sender that reaches the interface). See
:mod:`tracking.osc_input` for what is received and how bad packets are counted. TUIO objects
become puck measurements whose marker id is the class id, so ``tracking.puck_ids`` and the
tracker's identity, jitter filter and coasting apply to them as to camera pucks.
"""

from __future__ import annotations

import ipaddress
import re
from typing import Any

from tabletop.registry import BuildContext
from tabletop.schema import Context, ListOf, Number, Record, Spec, Str, shown
from tracking.osc_input import OscInput


class IPAddress(Str):
    """An IPv4 or IPv6 address written out (no host names: an allow-list must not depend on DNS)."""

    def describe(self) -> str:
        return "an IP address such as 127.0.0.1 or 192.168.1.20"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        value = super().validate(value, path, ctx)
        try:
            return str(ipaddress.ip_address(value))
        except ValueError:
            pass
        bare = value[1:-1] if value[:1] == "[" and value[-1:] == "]" else None
        try:   # as a URL or ``tabletop status`` writes it: [::1]
            hint = f" (an IPv6 address is written bare here: {ipaddress.ip_address(bare)})"
        except ValueError:
            hint = ""
        raise ctx.error(path, f"expected {self.describe()}, got {shown(value)}{hint}")


class HostName(IPAddress):
    """Where datagrams go: an IP address, or a host name (letters, digits, hyphens and dots,
    its last label not all digits; looked up when sending, so a name that does not resolve yet
    is not refused at load)."""

    NAME = re.compile(r"(?=.{1,253}\Z)(?:[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?\.)*"
                      r"(?=[A-Za-z0-9-]*[A-Za-z-])[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?"
                      r"\.?\Z")

    def describe(self) -> str:
        return "an IP address or a host name such as 192.168.1.255 or table-7.local"

    def validate(self, value: Any, path: str, ctx: Context) -> Any:
        if isinstance(value, str) and self.NAME.match(value):
            return value
        return super().validate(value, path, ctx)


def port_spec(default: int, doc: str, lo: int = 0) -> Spec:
    """A UDP port; ``lo`` 0 lets a listener take any free port, a destination needs 1."""
    return Number(default, integer=True, lo=lo, hi=65535, doc=doc)


SCHEMA = Record({
    "host": IPAddress("127.0.0.1", doc="interface address to listen on (0.0.0.0: every "
                                       "interface)"),
    "port": port_spec(3333, "UDP port (TUIO's default is 3333)"),
    "allow": ListOf(IPAddress(), default=[], doc="sender addresses accepted (empty: any)"),
    "quiet_s": Number(1.5, lo=0.05, hi=60.0,
                      doc="a sender silent this long is gone: its pucks coast, its touches and "
                          "streams leave (reference servers resend their state every second)"),
    "stall_s": Number(5.0, lo=0.1, hi=3600.0,
                      doc="health turns bad when nothing was received this long"),
    "max_packet": Number(16384, integer=True, lo=512, hi=65536,
                         doc="larger datagrams are refused, bytes"),
})


def build(options: dict, ctx: BuildContext) -> OscInput:
    return OscInput(options["name"], options["host"], options["port"], options["allow"],
                    ctx.table, quiet_s=options["quiet_s"], stall_s=options["stall_s"],
                    max_packet=options["max_packet"])
