"""systemd's notify protocol (sd_notify), without a dependency: one unix datagram per message.

The service manager (or :mod:`tabletop.kiosk.supervisor`, which relays to it) names its socket in
``$NOTIFY_SOCKET``: a filesystem path, or an abstract socket when it starts with ``@``. Messages
are newline-separated ``KEY=VALUE`` assignments such as ``READY=1``, ``WATCHDOG=1``,
``STATUS=...``, ``STOPPING=1``. Without ``$NOTIFY_SOCKET`` every call does nothing.
"""

from __future__ import annotations

import os
import socket


def socket_address(name: str) -> str | bytes:
    """The ``sendto`` address of a ``$NOTIFY_SOCKET`` value (``@`` = abstract namespace)."""
    return b"\0" + name[1:].encode() if name.startswith("@") else name


class Notifier:
    """Sends notify messages to ``$NOTIFY_SOCKET`` (read once); never raises."""

    def __init__(self, address: str | None = None) -> None:
        self.address = address if address is not None else os.environ.get("NOTIFY_SOCKET")
        self._sock: socket.socket | None = None
        self.sent = 0

    @property
    def enabled(self) -> bool:
        return bool(self.address)

    def send(self, message: str) -> bool:
        """Send one message (e.g. ``"READY=1"``); False when there is no socket or it failed."""
        if not self.address:
            return False
        try:
            if self._sock is None:
                self._sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
            self._sock.sendto(message.encode(), socket_address(self.address))
        except OSError:
            return False
        self.sent += 1
        return True

    def close(self) -> None:
        if self._sock is not None:
            self._sock.close()
            self._sock = None
