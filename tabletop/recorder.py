"""Session recordings: JSON Lines, a header line then one frame per line.

Header: ``{"format": "tabletop-session", "version": 1, "created": ISO date, "config": {...},
"calibration": {...} | null}``. Frame lines carry seq, t (seconds, relative to the recording's
first frame, see DESIGN.md "Time"), pucks, touches, streams, characters and commands, with floats
written exactly (shortest repr round-trips). Every line is handed to the operating system as it
is written (a killed process loses at most the line being written) and a background thread
syncs the file to disk twice a second (a power cut loses at most that much); it is fsynced when
closed. A reader accepts a recording whose last line was cut short and says so.
"""

from __future__ import annotations

import datetime as _dt
import json
import logging
import math
import os
import threading
from pathlib import Path
from typing import Any, Iterator

import numpy as np

from tabletop.frames import CharacterState, Frame, InputError, Puck, Touch

log = logging.getLogger("tabletop")

FORMAT = "tabletop-session"
VERSION = 1


class SessionError(InputError):
    """A session recording is missing or malformed; names the file and line."""


def _num(v: float) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def _unnum(v: Any) -> float:
    return math.nan if v is None else float(v)


def frame_to_dict(frame: Frame, t0: float = 0.0) -> dict[str, Any]:
    """A JSON-able dict of the frame with its time made relative to ``t0``."""
    return {
        "seq": frame.seq,
        "t": frame.t - t0,
        "pucks": [{"id": p.id, "x": p.x, "y": p.y, "angle": p.angle, "vx": p.vx, "vy": p.vy,
                   "omega": p.omega, "state": p.state, "raw_x": _num(p.raw_x),
                   "raw_y": _num(p.raw_y), "raw_angle": _num(p.raw_angle)} for p in frame.pucks],
        "touches": [{"id": c.id, "x": c.x, "y": c.y, "vx": c.vx, "vy": c.vy} for c in frame.touches],
        "streams": {k: v.tolist() for k, v in frame.streams.items()},
        "characters": [_character_to_dict(c) for c in frame.characters],
        "commands": list(frame.commands),
        **({"focus": frame.focus} if frame.focus is not None else {}),
    }


def _character_to_dict(c: CharacterState) -> dict[str, Any]:
    d: dict[str, Any] = {"name": c.name, "x": c.x, "y": c.y, "heading": c.heading, "kind": c.kind,
                         "size": c.size, "color": list(c.color), "valid": c.valid}
    if c.progress is not None:
        d["progress"] = _num(c.progress)
    if c.action is not None:
        d["action"] = c.action
    if c.points is not None:
        d["points"] = c.points.tolist()
        d["bones"] = [list(b) for b in c.bones]
    if c.label:
        d["label"] = c.label
    return d


def frame_from_dict(d: dict[str, Any]) -> Frame:
    """Inverse of :func:`frame_to_dict` (times stay relative to the recording's start)."""
    pucks = tuple(Puck(int(p["id"]), float(p["x"]), float(p["y"]), float(p["angle"]),
                       float(p.get("vx", 0.0)), float(p.get("vy", 0.0)), float(p.get("omega", 0.0)),
                       p.get("state", "seen"), _unnum(p.get("raw_x")), _unnum(p.get("raw_y")),
                       _unnum(p.get("raw_angle"))) for p in d.get("pucks", []))
    touches = tuple(Touch(int(c["id"]), float(c["x"]), float(c["y"]), float(c.get("vx", 0.0)),
                          float(c.get("vy", 0.0))) for c in d.get("touches", []))
    streams = {k: np.asarray(v, dtype=float) for k, v in d.get("streams", {}).items()}
    characters = tuple(
        CharacterState(c["name"], float(c["x"]), float(c["y"]), float(c["heading"]),
                       kind=c.get("kind", "reactor"), size=float(c.get("size", 0.08)),
                       color=tuple(c.get("color", (240, 170, 60))),
                       points=None if c.get("points") is None else np.asarray(c["points"], float),
                       bones=tuple(tuple(b) for b in c.get("bones", ())),
                       progress=None if "progress" not in c else _unnum(c["progress"]),
                       action=c.get("action"), valid=bool(c.get("valid", True)),
                       label=c.get("label", ""))
        for c in d.get("characters", []))
    return Frame(seq=int(d["seq"]), t=float(d["t"]), pucks=pucks, touches=touches,
                 streams=streams, characters=characters, commands=tuple(d.get("commands", ())),
                 focus=d.get("focus"))


def jsonable(value: Any) -> Any:
    """Config values (paths, tuples, numpy numbers) as plain JSON types."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, np.generic):
        return value.item()
    return value


class Recorder:
    """Sink writing every frame to a session file (JSON Lines)."""

    name = "recorder"

    def __init__(self, path: str | Path, config: dict[str, Any] | None = None,
                 calibration: dict[str, Any] | None = None, flush_every_s: float = 0.5) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if self.path.exists():
            raise SessionError(f"{self.path}: already exists; a recording is never overwritten")
        self._f = open(self.path, "x", encoding="utf-8")
        header = {"format": FORMAT, "version": VERSION,
                  "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                  "config": jsonable(config or {}), "calibration": jsonable(calibration)}
        self._f.write(json.dumps(header, separators=(",", ":")) + "\n")
        self._f.flush()
        self._t0: float | None = None
        self.flush_every_s = flush_every_s
        self.frames = 0
        self._dirty = threading.Event()
        self._closing = threading.Event()
        self._syncer = threading.Thread(target=self._sync, name="recorder-sync", daemon=True)
        self._syncer.start()

    def _sync(self) -> None:
        """Sync written lines to disk, at most every ``flush_every_s``, off the frame loop."""
        fd = self._f.fileno()
        while not self._closing.is_set():
            if self._dirty.wait(0.5) and not self._closing.is_set():
                self._dirty.clear()
                try:
                    os.fdatasync(fd)
                except OSError as exc:
                    log.warning("recording %s: sync failed: %s", self.path, exc)
                self._closing.wait(self.flush_every_s)

    def consume(self, frame: Frame) -> None:
        if self._f.closed:
            return
        if self._t0 is None:
            self._t0 = frame.t
        self._f.write(json.dumps(frame_to_dict(frame, self._t0), separators=(",", ":"),
                                 allow_nan=False) + "\n")
        self.frames += 1
        self._f.flush()
        self._dirty.set()

    def close(self) -> None:
        if self._f.closed:
            return
        self._closing.set()
        self._syncer.join()
        self._f.flush()
        os.fsync(self._f.fileno())
        self._f.close()
        log.info("recording %s: %d frames", self.path, self.frames)


def read_header(path: str | Path) -> dict[str, Any]:
    """The header of a session file; raises SessionError if it is not one."""
    p = Path(path)
    try:
        with open(p, encoding="utf-8") as f:
            first = f.readline()
    except FileNotFoundError:
        raise SessionError(f"{p}: session recording not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SessionError(f"{p}: cannot read session recording: {exc}") from None
    if not first.strip():
        raise SessionError(f"{p}: empty file; expected a {FORMAT} header line")
    try:
        header = json.loads(first)
    except json.JSONDecodeError as exc:
        raise SessionError(f"{p}: line 1: not a JSON header ({exc.msg})") from None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise SessionError(f"{p}: line 1: not a {FORMAT} header")
    if header.get("version") != VERSION:
        raise SessionError(f"{p}: line 1: version {header.get('version')!r} is not supported "
                           f"(this tabletop reads version {VERSION})")
    return header


def read_frames(path: str | Path) -> Iterator[Frame]:
    """The frames of a session file, in order. A malformed line raises SessionError naming it,
    except a cut-short last line, which is skipped with a warning."""
    p = Path(path)
    read_header(p)
    with open(p, encoding="utf-8") as f:
        lines = iter(enumerate(f, start=1))
        next(lines)
        pending: tuple[int, str] | None = None
        for item in lines:
            if pending is not None:
                yield _parse_line(p, *pending)
            pending = item
        if pending is not None:
            n, line = pending
            if not line.endswith("\n"):
                try:
                    yield _parse_line(p, n, line)
                except SessionError:
                    log.warning("%s: line %d is cut short (the recording was interrupted); "
                                "skipped", p, n)
            else:
                yield _parse_line(p, n, line)


def _parse_line(p: Path, n: int, line: str) -> Frame:
    try:
        return frame_from_dict(json.loads(line))
    except (json.JSONDecodeError, KeyError, TypeError, ValueError) as exc:
        raise SessionError(f"{p}: line {n}: not a valid frame ({exc})") from None
