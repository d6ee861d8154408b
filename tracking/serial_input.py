"""Serial input: a microcontroller (or anything pyserial opens) sending ASCII lines, in its own
thread.

The line protocol (DESIGN.md): lines end with ``\\n`` or ``\\r\\n``, fields are split on spaces,
at most ``MAX_LINE`` bytes a line (NUL padding at either end of a line is dropped)::

    puck ID X Y ANGLE      table metres, radians
    touch ID X Y           table metres
    lift ID                the touch ID has lifted
    stream NAME V1 V2 ...  a named vector of floats
    # comment              (also after a command)

:func:`parse_line` is the pure codec (one line -> one command, or :class:`LineError` whose
``kind`` names its counter); :class:`LineSplitter` cuts a byte stream into lines in bounded
memory (an over-long line is counted and skipped up to its newline); :class:`SerialState` keeps
what the lines said, and forgets a puck, touch or stream not repeated for ``timeout_s``.
:class:`SerialInput` is the ``Source``: it opens ``port`` (a device or any pyserial URL such as
``loop://`` or ``socket://HOST:PORT``), reads in its thread, and when the device vanishes closes
it and reopens it with a doubling back-off, saying so in its health as the camera does.

Silence, where the config asks for it (``stall_s``; off by default, because the serial
contract lets a device say nothing while the table is empty): an open port that has delivered
no valid line (a command, a comment or a blank line) for ``stall_s`` is unhealthy, with "no
valid line for N s" in its health, and healthy again with the next valid line. A board that hung
with its USB port still enumerated, or a cable whose data line broke, kept the port open and
the status "open" for hours while no position arrived. A device that sends a comment
(``# idle``) or a blank line at least every ``stall_s`` is told apart from one that hung; bad
lines do not count (garbage is not a device that works).
"""

from __future__ import annotations

import logging
import math
import re
import threading
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from tabletop.frames import (MAX_FEATURE, MAX_MARKER_ID, Observation,
                             PuckMeasurement, SourceHealth, Touch, wrap_angle)
from tracking.badinput import BackgroundSource, BadInput, CountedError, RetryLog

log = logging.getLogger("tabletop.serial")

MAX_LINE = 1024
HOLD_S = 0.1           # an observation is stamped at most this old (the clock moves on)
MAX_ID = MAX_MARKER_ID
MAX_COORD = 100.0          # metres; farther is refused
MAX_ITEMS = 256            # pucks, touches (each)
MAX_STREAMS = 64
MAX_STREAM_VALUES = 256
NAME = re.compile(r"[A-Za-z0-9_.\-]{1,64}\Z")
BARE_CR = re.compile(rb"\r[^\n\0]")   # a \r that ends no line (NUL padding may follow one)


class LineError(CountedError):
    """A serial line is wrong; ``kind`` is its counter name."""


@dataclass(frozen=True, slots=True)
class Command:
    """One parsed line: ``verb`` (puck, touch, lift, stream), ``id`` or ``name``, ``values``."""

    verb: str
    id: int = -1
    name: str = ""
    values: tuple[float, ...] = ()


# a number of a line: a plain decimal or float spelling (``-0.5``, ``3``, ``1e-3``), not the
# others Python's float() takes (``1_0``, which it reads as 10): a board's garbled digits are a
# malformed line, never a position; ``nan`` and ``inf`` are refused as non-finite
NUMERAL = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\Z")
NON_FINITE = re.compile(r"[-+]?(?:nan|inf|infinity)\Z", re.IGNORECASE)


def _number(text: str, what: str) -> float:
    if NON_FINITE.match(text):
        raise LineError("non_finite", f"{what} is {text[:40]}")
    if not NUMERAL.match(text):
        raise LineError("wrong_arguments", f"{what} {text[:40]!r} is not a number")
    v = float(text)
    if not math.isfinite(v):
        raise LineError("non_finite", f"{what} is {text[:40]}")
    return v


def _id(text: str) -> int:
    if not text.isdigit() or int(text) > MAX_ID:
        raise LineError("wrong_arguments", f"id {text[:40]!r} is not a whole number "
                                           f"0..{MAX_ID}")
    return int(text)


def parse_line(line: bytes) -> Command | None:
    """One line (without its newline) -> Command, or None for a blank line or a comment. NUL
    bytes at either end of the line are dropped: a board writing a whole fixed buffer
    (``Serial.write(buf, sizeof buf)``) pads after its newline, so the next line starts with
    them (and its ``\r\n`` may follow them); a NUL inside the line stays garbage."""
    try:
        text = line.strip(b"\0\r").decode("ascii")
    except UnicodeDecodeError:
        raise LineError("garbage", "line is not ASCII") from None
    fields = text.split("#", 1)[0].split()  # a comment may also end a line
    if not fields:
        return None
    verb, args = fields[0], fields[1:]
    arity = {"puck": 4, "touch": 3, "lift": 1}.get(verb)
    if arity is not None:
        if len(args) != arity:
            raise LineError("wrong_arguments", f"{verb} takes {arity} fields, got {len(args)}")
        pid = _id(args[0])
        values = tuple(_number(a, f"{verb} {pid} value") for a in args[1:])
        if any(abs(v) > MAX_COORD for v in values[:2]):
            raise LineError("out_of_range", f"{verb} {pid} at {values[:2]} is off the table")
        if verb == "puck":  # wrapped to (-pi, pi]: the tracker unwraps from differences, and
            # two huge angles (1e308, then -1e308) differ by an infinity it cannot wrap
            values = (*values[:2], wrap_angle(values[2]))
        return Command(verb, pid, values=values)
    if verb == "stream":
        if len(args) < 2 or len(args) > MAX_STREAM_VALUES + 1:
            raise LineError("wrong_arguments", f"stream takes a name and 1..{MAX_STREAM_VALUES} "
                                               f"values, got {len(args)} fields")
        if not NAME.match(args[0]):
            raise LineError("wrong_arguments", f"stream name {args[0][:40]!r} is not a name")
        values = tuple(_number(a, f"stream {args[0]} value") for a in args[1:])
        if max(map(abs, values)) > MAX_FEATURE:   # a followed stream became NaN
            raise LineError("out_of_range", f"stream {args[0]} has a value beyond "
                                            f"{MAX_FEATURE:g}")
        return Command("stream", name=args[0], values=values)
    if not verb.isprintable():
        raise LineError("garbage", "line has control characters")
    raise LineError("unknown_command", f"unknown command {verb[:40]!r}")


class LineSplitter:
    """Bytes in, complete lines out, holding at most ``max_line`` bytes of an unfinished line
    (and the ``\r`` of a ``\r\n`` ending: the limit counts the line, not its ending).

    A line longer than ``max_line`` is dropped up to its newline and counted in ``overlong``."""

    def __init__(self, max_line: int = MAX_LINE) -> None:
        self.max_line = max_line
        self._buf = bytearray()
        self._skipping = False
        self.overlong = 0
        self.overlong_upto = 0   # the last feed's bytes up to the end of its last overlong line

    def unfinished_is_ascii(self) -> bool:
        """Whether the unfinished line held so far is ASCII (empty: True)."""
        return self._buf.isascii()

    def feed(self, data: bytes) -> list[bytes]:
        """The lines that ``data`` completes (without their ``\n``; a ``\r`` before it kept)."""
        lines = []
        start = 0
        self.overlong_upto = 0
        while True:
            nl = data.find(b"\n", start)
            if nl < 0:
                break
            piece = data[start:nl]
            if not self._skipping and len(self._buf) + len(piece) <= self.max_line + 1:
                line = bytes(self._buf) + piece
                if len(line) - line.endswith(b"\r") <= self.max_line:  # \r\n ends it too
                    lines.append(line)
                else:
                    self.overlong += 1
                    self.overlong_upto = nl
            elif not self._skipping:
                self.overlong += 1
                self.overlong_upto = nl
            self._buf.clear()
            self._skipping = False
            start = nl + 1
        rest = data[start:]
        if not self._skipping:
            if len(self._buf) + len(rest) > self.max_line + 1:  # room for the \r of \r\n
                self.overlong += 1
                self.overlong_upto = len(data)
                self._skipping = True
                self._buf.clear()
            else:
                self._buf += rest
        return lines


class SerialState:
    """What the lines said, each item with the time it was last repeated (monotonic s)."""

    def __init__(self, timeout_s: float = 0.5) -> None:
        self.timeout_s = timeout_s
        self.pucks: dict[int, tuple[float, float, float, float]] = {}
        self.touches: dict[int, tuple[float, float, float]] = {}
        self.streams: dict[str, tuple[np.ndarray, float]] = {}

    def apply(self, c: Command, t: float) -> None:
        """Take command ``c`` heard at ``t`` (monotonic s); LineError("too_many") when a new
        item made room by forgetting the one repeated longest ago (the command still applies)."""
        if c.verb == "lift":
            self.touches.pop(c.id, None)
            return
        if c.verb == "stream":
            table: dict[Any, Any] = self.streams
            key, value = c.name, (np.array(c.values), t)
            limit = MAX_STREAMS
        elif c.verb == "puck":
            table, key, value, limit = self.pucks, c.id, (*c.values, t), MAX_ITEMS
        else:
            table, key, value, limit = self.touches, c.id, (*c.values, t), MAX_ITEMS
        full = key not in table and len(table) >= limit
        if full:  # the one repeated longest ago makes room: the newest input always gets in
            oldest = min(table, key=lambda k: table[k][-1])
            del table[oldest]
        table[key] = value
        if full:
            raise LineError("too_many", f"more than {limit} {c.verb}s at once: "
                                        f"{oldest} forgotten")

    def expire(self, t: float) -> list[int]:
        """Forget what was not repeated for ``timeout_s``; returns the puck ids forgotten."""
        gone = [k for k, v in self.pucks.items() if t - v[3] > self.timeout_s]
        for k in gone:
            del self.pucks[k]
        for k in [k for k, v in self.touches.items() if t - v[2] > self.timeout_s]:
            del self.touches[k]
        for k in [k for k, v in self.streams.items() if t - v[1] > self.timeout_s]:
            del self.streams[k]
        return gone


class SerialInput(BackgroundSource):
    """A ``Source`` reading the line protocol from ``port`` (see the module docstring).

    ``opener(port, baudrate)`` returns an open pyserial object (default
    ``serial.serial_for_url``); ``port_object`` is the one in use (tests write to ``loop://``
    through it). ``stall_s``: an open port silent this long (no valid line, seconds of
    ``clock``) is unhealthy; None: never."""

    def __init__(self, name: str, port: str, baudrate: int = 115200, timeout_s: float = 0.5,
                 retry_min_s: float = 0.5, retry_max_s: float = 8.0, stall_s: float | None = None,
                 opener: Callable[[str, int], Any] | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.name, self.port, self.baudrate = name, port, baudrate
        self.retry_min_s, self.retry_max_s, self.clock = retry_min_s, retry_max_s, clock
        self.stall_s = stall_s
        self.opener = opener or _open_serial
        self.state = SerialState(timeout_s)
        self.bad = BadInput(name, clock=clock)
        self._retries = RetryLog(name, log, clock=clock)
        self.port_object: Any = None
        self.lines = 0
        self.reconnects = 0
        self._lock = threading.Lock()
        self._init_thread()
        self._ok, self._message, self._retry_at = False, "starting", None
        self._heard_t = -math.inf    # the last command (stamps the observations)
        self._alive_t = -math.inf    # the port's opening or its last valid line (health)
        self._seq = 0
        self._emitted: set[int] = set()

    def latest(self) -> Observation | None:
        now = self.clock()
        with self._lock:
            self.state.expire(now)
            st = self.state
            held = now - HOLD_S  # present until timeout_s: a still puck is not a lost one
            pucks = tuple(PuckMeasurement(k, x, y, a, min(max(t, held), now))
                          for k, (x, y, a, t) in st.pucks.items())
            touches = tuple(Touch(k, x, y) for k, (x, y, _t) in st.touches.items())
            streams = {k: v for k, (v, _t) in st.streams.items()}
            ids = {p.id for p in pucks}
            removed = tuple(sorted(self._emitted - ids))
            self._emitted = ids
            if self._seq == 0 and not (pucks or touches or streams):
                return None
            self._seq += 1
            t = max(min(self._heard_t, now), now - HOLD_S)
        return Observation(self.name, t, self._seq, pucks=pucks, touches=touches,
                           streams=streams, removed=removed, held=t > self._heard_t)

    def health(self) -> SourceHealth:
        now = self.clock()
        with self._lock:
            ok, message, retry_at = self._ok, self._message, self._retry_at
            age = now - self._heard_t
            silent = now - self._alive_t
        if retry_at is not None:
            message = f"{message}; reconnecting in {max(0.0, retry_at - now):.1f} s"
        elif ok and self.stall_s is not None and silent > self.stall_s:
            ok, message = False, f"{message}; no valid line for {silent:.0f} s"
        return self.bad.health(ok, message, age)

    # ------------------------------------------------------------------ the thread
    def _set(self, ok: bool, message: str, retry_at: float | None = None) -> None:
        with self._lock:
            self._ok, self._message, self._retry_at = ok, message, retry_at
            if ok:   # just opened: its silence counts from now
                self._alive_t = self.clock()

    def _run(self) -> None:
        delay = self.retry_min_s
        opened_before = False
        while not self._stop.is_set():
            try:
                port = self.opener(self.port, self.baudrate)
            except Exception as exc:  # SerialException, OSError, ValueError from a bad URL
                reason = f"cannot open {self.port}: {open_failure(exc, self.port)}"
            else:
                if opened_before:
                    self.reconnects += 1
                opened_before = True
                self.port_object = port
                self._set(True, f"{self.port} open")
                reason, got_data = self._read(port)
                self.port_object = None
                try:
                    port.close()
                except Exception:
                    pass
                if got_data:
                    delay = self.retry_min_s
            if self._stop.is_set():
                break
            self._retries.failed(reason, delay)
            self._set(False, reason, self.clock() + delay)
            self._stop.wait(delay)
            delay = min(delay * 2.0, self.retry_max_s)
        self._set(False, "closed")

    def _read(self, port: Any) -> tuple[str, bool]:
        splitter = LineSplitter()
        got = False
        while not self._stop.is_set():
            try:
                data = port.read(max(1, min(port.in_waiting, 65536)))
            except Exception as exc:  # SerialException, OSError: unplugged, closed pty
                return f"{self.port} lost: {exc}", got
            if not data:
                continue  # read timed out: nothing sent
            if not got:
                self._retries.worked(self.port)
            got = True
            overlong = splitter.overlong
            held_ascii = splitter.unfinished_is_ascii()   # (the line's earlier reads)
            lines = splitter.feed(data)
            if splitter.overlong > overlong:   # (firmware ending lines with \r alone:
                # every line ran into the next, and "line over 1024 bytes" was all it said).
                # Not noise: judged on the whole overlong line, the reads held before this one
                # too (this read alone could be a plain stretch of line noise), and on this
                # read up to that line's end only (a \r of the next line's noise, read with it,
                # asked about an overlong line of plain text: the chunking of the reads)
                own = data[:splitter.overlong_upto]
                alone = " (lines ending in \\r alone? end them with \\n or \\r\\n)" \
                    if held_ascii and own.isascii() and BARE_CR.search(own) else ""
                self.bad.count("overlong", f"line over {MAX_LINE} bytes{alone}",
                               splitter.overlong - overlong)
            if lines:
                self._apply(lines, self.clock())
        return "closed", got

    def _apply(self, lines: list[bytes], t: float) -> None:
        """Parse and apply one read's ``lines``, taking the lock once per line. One lock per
        read was measured (200,000 lines through a pty, 60 Hz ``latest()`` beside): 3.66
        against 4.18 us of CPU a line; at 115,200 baud (at most about 520 lines a second) that
        is 0.3 ms a second, so the lock stays per line (``latest()`` never waits for a batch)."""
        for line in lines:
            try:
                c = parse_line(line)
                with self._lock:
                    self._alive_t = t    # a comment or a blank line says the device works
                    if c is not None:
                        self.state.apply(c, t)
                        self._heard_t = t
                        self.lines += 1
            except LineError as exc:
                self.bad.count(exc.kind, f"{exc}: {line[:60]!r}")
            except Exception as exc:  # a bug must not end the reading thread
                self.bad.count("internal_error", f"{type(exc).__name__}: {exc}")


def open_failure(exc: BaseException, port: str) -> str:
    """Why pyserial could not open ``port``, without its own repetitions ("[Errno 2] could not
    open port /dev/x: [Errno 2] No such file or directory: '/dev/x'" -> "No such file or
    directory")."""
    text = str(exc)
    if "exclusively lock" in text:   # (EAGAIN on the lock _open_serial takes)
        return "another program holds it (a second installation reading the same device?)"
    for pattern in (r"^(\[Errno -?\d+\] )?could not open port .*?: ", r"^\[Errno -?\d+\] ",
                    r": '" + re.escape(port) + r"'$"):
        text = re.sub(pattern, "", text, flags=re.IGNORECASE)
    return text or str(exc)


def _open_serial(port: str, baudrate: int) -> Any:
    """The port opened; a device (not a URL) locked for this process alone: two runs reading
    one device each got part of its lines, torn ("upuck 1 ...", "pck 1 ..."), the puck seen in
    148 and 199 of 475 frames and each run's port "lost" again and again."""
    import serial
    if "://" in port:
        return serial.serial_for_url(port, baudrate=baudrate, timeout=0.05)
    return serial.serial_for_url(port, baudrate=baudrate, timeout=0.05, exclusive=True)
