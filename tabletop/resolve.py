"""A UDP destination whose host name is looked up away from the frame loop.

The ``tuio`` sink and the kiosk heartbeat send from the frame loop. A host name looked up
there blocked the loop for as long as the system's resolver took: with a gallery's name server
not answering, 10 s per look-up (measured: glibc's 5 s timeout, two tries), so the installation
drew 266 frames in 20 s and a kiosk's stall watch (``stall_s`` 5) would kill it again and again.
Here an address (``127.0.0.1``, a broadcast address) is used at once, and a name is looked up
in a thread of its own, again ``RETRY_S`` after a failure, while the sender drops what it would
send; the failure is logged when its reason is new (again every 10 min) and the name's arrival
once, so a week without a name server writes a few lines.

A name is looked up again, in that thread, every ``REFRESH_S`` (30 s) and after a send that
failed (no sooner than ``RETRY_S`` after the last look-up): a receiver whose address changes
(DHCP) is reached again within 30 s, without a restart, and the frame loop never waits for a
look-up. Until the new look-up returns, and when it fails (a name server gone), datagrams go on
to the last address found. A name with several addresses (round-robin DNS, a multi-homed
receiver) keeps the address in use while a look-up still lists it, whatever their order, and
"moved" is logged only when it is no longer listed: the receiver never alternates. Looked up in
a thread rather than on the loop with a short timeout: glibc's resolver takes no timeout per
call (``/etc/resolv.conf`` sets it for the whole process). One thread per destination with a
name, started when the destination is made (at build, not on the loop) and ended by
:meth:`Destination.close`, waits for each look-up: the loop only sets an event (median 0.6 us)
where starting a thread per look-up cost it 53 us median, 4.0 ms p99 (300 starts, 2 cores at
load 2.3), a dropped frame's worth every so often.

:func:`host_port` reads a ``HOST:PORT`` given on a command line or in a URL, an IPv6 address in
brackets (``[::1]:9000``, as in URLs); :func:`shown_host_port` writes one back.
"""

from __future__ import annotations

import ipaddress
import logging
import socket
import threading
import time
from typing import Any, Callable

from tracking.badinput import RetryLog

Target = tuple[int, Any]   # (address family, socket address for sendto)

HOST_PORT = ("HOST:PORT (port 1..65535; an IPv6 address in brackets), e.g. 0.0.0.0:9000 or "
             "[::1]:9000")


def host_port(text: str) -> tuple[str, int]:
    """``"0.0.0.0:9000"`` -> ("0.0.0.0", 9000), ``"[::1]:9000"`` -> ("::1", 9000); ValueError
    with one message for anything else (``::1:9000`` too: its port would be a guess). The
    brackets are taken off the host: split at the last colon alone, ``[::1]:9000`` would be
    the host ``[::1]``, which no socket takes."""
    host, sep, port = text.rpartition(":")
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
        try:
            ipaddress.IPv6Address(host)
        except ValueError:
            host = ""
    elif ":" in host or "[" in host or "]" in host:
        host = ""
    n = int(port) if port.isascii() and port.isdigit() and len(port) <= 5 else 0
    if not sep or not host or not 0 < n < 65536:
        raise ValueError(f"{text!r}: expected {HOST_PORT}")
    return host, n


def shown_host_port(host: str, port: int) -> str:
    """``HOST:PORT`` as :func:`host_port` reads it (an IPv6 address in brackets)."""
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


class Destination:
    """``(host, port)`` for UDP datagrams; ``target()`` is None until the host is known."""

    RETRY_S = 5.0   # seconds between look-ups of a name that did not resolve
    REFRESH_S = 30.0   # seconds between look-ups of a name that resolved (its address may move)

    def __init__(self, name: str, host: str, port: int, logger: logging.Logger,
                 clock: Callable[[], float] = time.monotonic, blocking: bool = True) -> None:
        self.host, self.port, self.clock = host, int(port), clock
        self.blocking = blocking   # the socket's mode (see :meth:`sendto`)
        self._sock: socket.socket | None = None
        self._log = RetryLog(name, logger)
        self._lock = threading.Lock()
        self._target: Target | None = None
        self._looking = False
        self._retry_at = -float("inf")
        self._refresh_at = float("inf")   # the next look-up of a name found (none: an address)
        self._looked_at = -float("inf")   # the last look-up's start
        # a look-up is asked of the thread; one Event per thread: a closed thread scheduled late
        # clears its own, never a request to the thread that replaced it
        self._due = threading.Event()
        self._thread: threading.Thread | None = None
        try:   # an address needs no look-up
            self._target = self._lookup(socket.AI_NUMERICHOST)[0]
        except OSError:
            self._start()

    def _lookup(self, flags: int = 0) -> list[Target]:
        """Every address of the host, in the resolver's order, each once."""
        info = socket.getaddrinfo(self.host, self.port, type=socket.SOCK_DGRAM, flags=flags)
        return list(dict.fromkeys((i[0], i[4]) for i in info))

    def _start(self) -> None:
        """A new look-up thread with its own request Event (called under ``_lock``, or from
        ``__init__``)."""
        self._due = due = threading.Event()
        self._thread = threading.Thread(target=self._serve, args=(due,),
                                        name=f"resolve:{self.host}", daemon=True)
        self._thread.start()

    def _serve(self, due: threading.Event) -> None:
        """The look-up thread: one look-up each time :meth:`target` sets ``due`` (this thread's
        own), until closed (it is then no longer ``_thread``)."""
        me = threading.current_thread()
        while True:
            due.wait()
            due.clear()
            if self._thread is not me:
                return
            self._resolve()

    def target(self) -> Target | None:
        """The family and socket address to send to, or None while the name is not known (a
        look-up is asked then, unless one runs or the last failed under ``RETRY_S`` ago). A
        name found is looked up again at ``_refresh_at``, its last address returned meanwhile."""
        with self._lock:
            now, target = self.clock(), self._target
            if self._looking or now < (self._retry_at if target is None else self._refresh_at):
                return target
            self._looking, self._looked_at = True, now
            if self._thread is None:   # closed, then sent on
                self._start()
            due = self._due
        due.set()
        return target

    def _resolve(self) -> None:
        try:
            addresses = self._lookup()
            reason = ""
        except (OSError, UnicodeError) as exc:
            addresses, reason = [], getattr(exc, "strerror", None) or str(exc)
        with self._lock:
            old = self._target
            now = self.clock()
            found = (old if old in addresses else addresses[0]) if addresses else None
            if found is None:
                self._retry_at = now + self.RETRY_S
                self._refresh_at = now + self.RETRY_S   # the last address is kept meanwhile
            else:
                self._target, self._refresh_at = found, now + self.REFRESH_S
        if found is None:
            self._log.failed(f"cannot resolve {self.host}: {reason}", self.RETRY_S)
        else:
            self._log.worked(f"{self.host} resolved,")
            if old is not None and old != found:
                self._log.log.info("%s: %s moved from %s to %s", self._log.name, self.host,
                                      old[1][0], found[1][0])
        # the look-up ends once it is said: `wait` returned before the warning was logged and a
        # test reading the log right after it found none (one run in a loaded suite)
        with self._lock:
            self._looking = False

    def sendto(self, data: bytes) -> bool:
        """Send one datagram; False (nothing sent) while the host name is not known. The socket,
        of the target's family with broadcast allowed, is made at the first send; OSError as
        ``socket.sendto`` raises it, and the name is looked up again (``RETRY_S`` after the
        last look-up at the soonest)."""
        target = self.target()
        if target is None:
            return False
        if self._sock is not None and self._sock.family != target[0]:
            self._close_socket()       # the name moved to the other address family
        if self._sock is None:
            sock = socket.socket(target[0], socket.SOCK_DGRAM)
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
            sock.setblocking(self.blocking)
            self._sock = sock
        try:
            self._sock.sendto(data, target[1])
        except OSError:
            with self._lock:
                if self._refresh_at != float("inf"):   # a name (an address is not looked up)
                    self._refresh_at = min(self._refresh_at, self._looked_at + self.RETRY_S)
            raise
        return True

    def close(self) -> None:
        """Close the socket, if one was made, and end the look-up thread (a later send makes
        both again)."""
        self._close_socket()
        with self._lock:   # (a look-up asked and not made is asked again by a later send)
            thread, self._thread, self._looking = self._thread, None, False
            due = self._due
        if thread is not None:
            due.set()

    def _close_socket(self) -> None:
        if self._sock is not None:
            self._sock.close()
            self._sock = None

    def wait(self, timeout: float) -> Target | None:
        """The target, waiting up to ``timeout`` s for a look-up under way (tests, tools)."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            target = self.target()
            with self._lock:
                if target is not None or not self._looking:
                    return target
            time.sleep(0.01)
        return self.target()
