"""Sink ``tuio``: pucks, touches and listed characters out as TUIO 1.1 over UDP.

Every frame, one ``/tuio/2Dobj`` bundle (source ``tabletop@HOSTNAME``, alive, a set per puck
(class id = puck id) and per listed character (class id from ``characters``), fseq) and one
``/tuio/2Dcur`` bundle for the touches; a bundle over 4096 bytes is split, each part with its
own alive and fseq, as reference servers do. With ``changes_only`` a set is sent only for an
entity that changed, as the reference server does, plus the full state every ``full_every_s``.
Positions go through the inverse of the ``osc`` source's mapping
(:func:`tracking.tuio.from_table`). Session ids are stable while a thing stays and never reused;
fseq rises by one a frame and, an int32, starts again at 1 after 2**31 - 1 (receivers take the
jump back for a restarted sender). Sending never blocks the loop (a host name is looked up in
the background, :mod:`tabletop.resolve`); a failed send is counted and logged at a limited
rate. ``sent`` counts the bundles handed to the network, ``unresolved`` those dropped while the
host name was not known.
"""

from __future__ import annotations

import logging
import math
import socket
from typing import Any, Callable

from tabletop.frames import Frame
from tabletop.plugins.osc import HostName, port_spec
from tabletop.registry import BuildContext
from tabletop.resolve import Destination
from tabletop.schema import Bool, Context, MapOf, Number, Optional_, Record, Str
from tracking.badinput import BadInput
from tracking.tuio import MAX_FSEQ, MAX_SOURCE, from_table, profile_bundles, set_args

log = logging.getLogger("tabletop.tuio")
# a listed character no frame has shown for this long is named once in the log (a typo in
# ``characters`` otherwise sends nothing, silently); seconds of frame time
UNSEEN_AFTER_S = 10.0


def _check_source(options: dict, path: str, ctx: Context) -> None:
    """A source name receivers keep whole: a 70 kB one made every datagram fail ("Message too
    long", one warning) for the whole run, and receivers cut it to MAX_SOURCE characters."""
    source = options["source"]
    if source is not None and not 0 < len(source) <= MAX_SOURCE:
        raise ctx.error(f"{path}.source", f"{len(source)} characters; expected 1 to "
                                          f"{MAX_SOURCE} (a name such as tracker@table-7)")


SCHEMA = Record({
    "host": HostName("127.0.0.1", doc="receiver address (an IP address or host name; a "
                                      "broadcast address reaches a whole network)"),
    "port": port_spec(3333, "receiver UDP port", lo=1),
    "characters": MapOf(Number(integer=True, lo=0, hi=2**31 - 1), default={},
                        doc="character name -> TUIO class id, sent as objects"),
    "source": Optional_(Str(), doc="TUIO source name (default tabletop@HOSTNAME), at most "
                                   f"{MAX_SOURCE} characters"),
    "changes_only": Bool(False, doc="send a set only for what changed (as TuioServer does), "
                                    "plus the full state every full_every_s"),
    "full_every_s": Number(1.0, lo=0.05, hi=60.0, doc="full-state resend period, seconds"),
    "touches": Bool(True, doc="send the touches as /tuio/2Dcur"),
}, check=_check_source)



class Sessions:
    """Stable TUIO session ids: one per key while the key stays, a new one when it comes back."""

    def __init__(self) -> None:
        self.ids: dict[Any, int] = {}
        self.next_id = 1

    def update(self, keys: list[Any]) -> list[int]:
        """Session ids of ``keys`` (in order); keys not listed are forgotten."""
        ids = {}
        for k in keys:
            sid = self.ids.get(k)
            if sid is None:
                sid, self.next_id = self.next_id, (self.next_id % (2**31 - 1)) + 1
            ids[k] = sid
        self.ids = ids
        return [ids[k] for k in keys]


class TuioSink:
    """Sends each frame as TUIO 1.1 bundles to ``address`` (host, port); see the module
    docstring. ``send(bundle)`` is the transport (a UDP socket by default); it returns False
    for a bundle it dropped without sending."""

    def __init__(self, name: str, address: tuple[str, int], table: tuple[float, float],
                 characters: dict[str, int] | None = None, source: str | None = None,
                 full_every_s: float = 1.0, touches: bool = True, changes_only: bool = False,
                 send: Callable[[bytes], bool | None] | None = None) -> None:
        self.name, self.address, self.table = name, address, table
        self.characters = dict(characters or {})
        self._unseen, self._seen = set(self.characters), set()
        self._clashed: set[str] = set()   # characters named sharing a puck's class id
        self._first_t: float | None = None
        self.source = source or f"tabletop@{socket.gethostname()}"
        self.full_every_s, self.with_touches = full_every_s, touches
        self.changes_only = changes_only
        self.bad = BadInput(name)
        self.fseq = 0
        self.sent = 0
        self._objects, self._cursors = Sessions(), Sessions()
        self._last: dict[tuple[str, int], tuple] = {}
        self._full_t = -math.inf
        # a host name is looked up away from the frame loop, once (see tabletop.resolve)
        self.destination = Destination(name, address[0], address[1], log, blocking=False)
        self.unresolved = 0   # bundles dropped while the host name was not known
        self._send = send or self._udp_send

    def _udp_send(self, data: bytes) -> bool:
        if self.destination.sendto(data):
            return True
        self.unresolved += 1
        return False

    def bundles(self, frame: Frame) -> list[bytes]:
        """The bundles of one frame (pure apart from session ids, fseq and change tracking)."""
        # an int32 on the wire: after MAX_FSEQ frames (414 days at 60 Hz) it starts again at
        # 1, a backwards jump receivers take for a restarted sender (it raised every frame)
        self.fseq = self.fseq % MAX_FSEQ + 1
        full = not self.changes_only or frame.t - self._full_t >= self.full_every_s
        if full:
            self._full_t = frame.t
        objects: list[tuple[Any, int, tuple]] = []
        for p in frame.pucks:
            objects.append((("puck", p.id), p.id,
                            from_table(p.x, p.y, p.angle, p.vx, p.vy, p.omega, self.table)))
        if self._unseen:
            self._check_listed(frame)
        if self.characters:   # none by default: no set of puck ids (0.4 us a frame of 8 pucks)
            pucks = {p.id for p in frame.pucks}
            for c in frame.characters:
                cid = self.characters.get(c.name)
                if cid is not None:
                    if cid in pucks and c.name not in self._clashed:
                        self._clashed.add(c.name)
                        log.warning("%s: character %s is sent with class id %d, which puck %d "
                                    "has too: a receiver takes it for a second sighting of that "
                                    "puck; give it an id no puck's marker has", self.name, c.name,
                                    cid, cid)
                    objects.append((("character", c.name), cid,
                                    from_table(c.x, c.y, c.heading, 0.0, 0.0, 0.0, self.table)))
        out = self._profile("2Dobj", self._objects, objects, full)
        if self.with_touches:
            cursors = [(("touch", tc.id), -1, from_table(tc.x, tc.y, 0.0, tc.vx, tc.vy, 0.0,
                                                         self.table)) for tc in frame.touches]
            out += self._profile("2Dcur", self._cursors, cursors, full)
        return out

    def _check_listed(self, frame: Frame) -> None:
        """Name, once, the listed characters no frame has shown in ``UNSEEN_AFTER_S``."""
        self._seen.update(c.name for c in frame.characters)
        self._unseen -= self._seen
        if self._first_t is None:
            self._first_t = frame.t
        if self._unseen and frame.t - self._first_t >= UNSEEN_AFTER_S:
            log.warning("%s: characters %s are listed in its 'characters' but no engine has "
                        "shown them in %g s (characters seen: %s)", self.name,
                        ", ".join(sorted(self._unseen)), UNSEEN_AFTER_S,
                        ", ".join(sorted(self._seen)) or "none")
            self._unseen = set()

    def _profile(self, profile: str, sessions: Sessions, items: list, full: bool) -> list[bytes]:
        items = [it for it in items if all(math.isfinite(v) for v in it[2])]
        sids = sessions.update([k for k, _, _ in items])
        sets = []
        for sid, (_, cid, values) in zip(sids, items):
            args = set_args(profile, sid, cid, values)
            if full or self._last.get((profile, sid)) != args:
                sets.append(args)
            self._last[(profile, sid)] = args
        live = set(sids)
        for key in [k for k in self._last if k[0] == profile and k[1] not in live]:
            del self._last[key]
        return profile_bundles(profile, self.source, sids, sets, self.fseq)

    def consume(self, frame: Frame) -> None:
        for b in self.bundles(frame):
            try:
                if self._send(b) is not False:   # a dropped bundle was not sent
                    self.sent += 1
            except OSError as exc:  # no route, buffer full, receiver gone: try next frame
                self.bad.count("send_failed", f"to {self.address[0]}:{self.address[1]}: {exc}")

    def close(self) -> None:
        self.destination.close()


def build(options: dict, ctx: BuildContext) -> TuioSink:
    return TuioSink(options["name"], (options["host"], options["port"]), ctx.table,
                    options["characters"], options["source"], options["full_every_s"],
                    options["touches"], options["changes_only"])
