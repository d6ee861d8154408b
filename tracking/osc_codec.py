"""OSC 1.0 packets as pure functions: bytes <-> (address, arguments) messages. No sockets here.

``decode_packet(data)`` turns one UDP datagram (a message or a bundle) into its messages in
order, bundles inside bundles flattened as oscpack's reference receiver does, and raises
:class:`OscError` (the one error of this layer) for anything malformed: truncated strings or
arguments, unknown type tags, sizes that point outside the packet, nesting deeper than
``max_depth``, more than ``max_messages``. Timetags are read and ignored (TUIO sends
"immediately"). ``encode_message`` and ``encode_bundle`` build packets; ints are int32 ``i``,
floats float32 ``f``, str ``s``, bytes ``b``, True/False/None ``T``/``F``/``N``.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Any, Sequence

from tabletop.frames import InputError

BUNDLE_TAG = b"#bundle\x00"
IMMEDIATELY = 1  # the timetag meaning "now"
MAX_DEPTH = 8
MAX_MESSAGES = 4096

_I32 = struct.Struct(">i")
_F32 = struct.Struct(">f")
_U64 = struct.Struct(">Q")
_FIXED = frozenset("ifdhtcrm")  # fixed-size type tags (int32, float32, double, int64, ...)
_CONSTANTS = {"T": True, "F": False, "N": None, "I": float("inf")}


class OscError(InputError):
    """An OSC packet is malformed; the message says what and at which byte."""


@dataclass(frozen=True, slots=True)
class Packet:
    """A decoded datagram: its messages in order and ``depth`` (0: a bare message, 1: a bundle,
    2 and more: bundles inside bundles)."""

    messages: tuple[tuple[str, tuple[Any, ...]], ...]
    depth: int


def _string(data: bytes, i: int, end: int) -> tuple[str, int]:
    z = data.find(b"\x00", i, end)
    if z < 0:
        raise OscError(f"unterminated string at byte {i}")
    try:
        s = data[i:z].decode("utf-8")
    except UnicodeDecodeError:
        raise OscError(f"string at byte {i} is not UTF-8") from None
    nxt = (z + 4) & ~3
    if nxt > end:
        raise OscError(f"string padding at byte {z} runs past the end")
    return s, nxt


_RUNS: dict[str, list[tuple[str, str | None]]] = {}
_HEADS: dict[bytes, tuple[str, list[tuple[str, str | None]]]] = {}  # address + tags bytes
_STRUCTS: dict[str, struct.Struct] = {}


def _runs(tags: str) -> list[tuple[str, str | None]]:
    """Type tags cut into (run of fixed-size tags, the variable tag after it or None)."""
    out = _RUNS.get(tags)
    if out is None:
        out, run = [], ""
        for tag in tags:
            if tag in _FIXED:
                run += tag
            else:
                out.append((run, tag))
                run = ""
        out.append((run, None))
        if len(_RUNS) < 256:  # type tag strings seen repeat; unusual ones are not kept
            _RUNS[tags] = out
    return out


def _struct(run: str) -> struct.Struct:
    st = _STRUCTS.get(run)
    if st is None:
        st = struct.Struct(">" + "".join("q" if t == "h" else "Q" if t == "t" else
                                         "i" if t in "crm" else t for t in run))
        if len(_STRUCTS) < 256:
            _STRUCTS[run] = st
    return st


def decode_message(data: bytes, start: int = 0, end: int | None = None
                   ) -> tuple[str, tuple[Any, ...]]:
    """One OSC message in ``data[start:end]`` -> (address, arguments)."""
    end = len(data) if end is None else end
    if end - start < 4 or data[start:start + 1] != b"/":
        raise OscError(f"message at byte {start} does not start with an address")
    z = data.find(b"\x00", start, end)
    if z >= 0 and (z + 4) & ~3 < end:  # the usual case: a known address and type tags
        zt = data.find(b"\x00", (z + 4) & ~3, end)
        head = _HEADS.get(data[start:zt]) if zt >= 0 else None
        if head is not None:
            address, runs = head
            i = (zt + 4) & ~3
            if i > end:
                raise OscError(f"type tag padding at byte {zt} runs past the end")
            return address, _arguments(data, i, end, address, runs)
    address, i = _string(data, start, end)
    if i >= end:
        return address, ()  # no type tag string: old senders; no arguments
    tags_at = i
    tags, i = _string(data, i, end)
    if not tags.startswith(","):
        raise OscError(f"type tags of {address} do not start with ','")
    runs = _runs(tags[1:])
    if len(_HEADS) < 256:  # headers repeat (one per message kind); unusual ones are not kept
        _HEADS[data[start:data.find(b"\x00", tags_at, end)]] = (address, runs)
    return address, _arguments(data, i, end, address, runs)


def _arguments(data: bytes, i: int, end: int, address: str,
               runs: list[tuple[str, str | None]]) -> tuple[Any, ...]:
    """The arguments starting at byte ``i``, typed by ``runs`` (see :func:`_runs`)."""
    args: list[Any] = []
    for run, tag in runs:
        if run:  # a run of fixed-size arguments: one struct call
            st = _struct(run)
            if i + st.size > end:
                raise OscError(f"{address}: arguments '{run}' at byte {i} are truncated")
            args.extend(st.unpack_from(data, i))
            i += st.size
        if tag is None:
            break
        if tag == "s" or tag == "S":
            s, i = _string(data, i, end)
            args.append(s)
        elif tag == "b":
            if i + 4 > end:
                raise OscError(f"{address}: blob size at byte {i} is truncated")
            n = _I32.unpack_from(data, i)[0]
            if n < 0 or i + 4 + n > end:
                raise OscError(f"{address}: blob of {n} bytes at byte {i} runs past the end")
            args.append(bytes(data[i + 4:i + 4 + n]))
            i = (i + 4 + n + 3) & ~3
        elif tag in _CONSTANTS:
            args.append(_CONSTANTS[tag])
        else:
            raise OscError(f"{address}: unknown type tag {tag!r}")
    return tuple(args)


def decode_packet(data: bytes, max_depth: int = MAX_DEPTH, max_messages: int = MAX_MESSAGES
                  ) -> Packet:
    """A datagram -> :class:`Packet`; raises :class:`OscError` when malformed."""
    if not data.startswith(BUNDLE_TAG):
        return Packet((decode_message(data),), 0)
    out: list[tuple[str, tuple[Any, ...]]] = []
    deepest = 1
    stack = [(len(BUNDLE_TAG) + 8, len(data), 1)]  # (next element, bundle end, depth)
    if len(data) < len(BUNDLE_TAG) + 8:
        raise OscError(f"bundle of {len(data)} bytes is shorter than its "
                       f"{len(BUNDLE_TAG) + 8}-byte header")
    while stack:
        i, end, depth = stack.pop()
        if i >= end:
            continue
        if i + 4 > end:
            raise OscError(f"bundle element size at byte {i} is truncated")
        n = _I32.unpack_from(data, i)[0]
        j = i + 4
        if n <= 0 or n % 4 or j + n > end:
            raise OscError(f"bundle element of {n} bytes at byte {i} does not fit its bundle")
        stack.append((j + n, end, depth))
        if data.startswith(BUNDLE_TAG, j):
            if depth + 1 > max_depth:
                raise OscError(f"bundles nested deeper than {max_depth}")
            if n < len(BUNDLE_TAG) + 8:
                raise OscError(f"nested bundle at byte {j} shorter than its header")
            deepest = max(deepest, depth + 1)
            stack.append((j + len(BUNDLE_TAG) + 8, j + n, depth + 1))
        else:
            out.append(decode_message(data, j, j + n))
            if len(out) > max_messages:
                raise OscError(f"more than {max_messages} messages in one packet")
    return Packet(tuple(out), deepest)


def _pad(b: bytes) -> bytes:
    return b + b"\x00" * (4 - len(b) % 4)


def encode_message(address: str, args: Sequence[Any] = ()) -> bytes:
    """An OSC message with type tags inferred from the Python types of ``args``."""
    tags = [","]
    body: list[bytes] = []
    for a in args:
        if a is True or a is False or a is None:
            tags.append("T" if a is True else "F" if a is False else "N")
        elif isinstance(a, int):
            tags.append("i")
            body.append(_I32.pack(a))
        elif isinstance(a, float):
            tags.append("f")
            body.append(_F32.pack(a))
        elif isinstance(a, str):
            tags.append("s")
            body.append(_pad(a.encode("utf-8")))
        elif isinstance(a, (bytes, bytearray)):
            tags.append("b")
            body.append(_I32.pack(len(a)) + bytes(a) + b"\x00" * (-len(a) % 4))
        else:
            raise TypeError(f"cannot encode {type(a).__name__} as an OSC argument")
    return _pad(address.encode("utf-8")) + _pad("".join(tags).encode()) + b"".join(body)


def encode_bundle(elements: Sequence[bytes], timetag: int = IMMEDIATELY) -> bytes:
    """A bundle of already encoded messages (or bundles)."""
    parts = [BUNDLE_TAG, _U64.pack(timetag)]
    for e in elements:
        parts.append(_I32.pack(len(e)))
        parts.append(e)
    return b"".join(parts)
