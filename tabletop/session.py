"""The session recording format: JSON Lines, a header line then one frame per line.

Header: ``{"format": "tabletop-session", "version": 2, "order": n (one more than the highest in
the folder when the file was made: what ``recorder.keep`` removes by), "session": id (16 hex
digits, one per session, a number in older recordings: ``keep`` removes a closed session's
parts together), "created":
ISO date,
"config": {...} (as written, validates again), "files": {NAME: {"text" | "base64", "sha256"}}
(every file the config refers to, see :mod:`tabletop.bundle`), "calibration": {...} | null,
"part": n}``, ``"reloaded"`` in a later part whose session reloaded files before it began
(:func:`tabletop.parts.carried`: played at its first frame when it is replayed first, so a part
replays on its own with what was reloaded before it), ``"performers"`` in a later part
(:func:`tabletop.parts.part_states`:
its engines' states before its first frame, which a part replayed first starts them from), and
``"studio": {"all": bool}`` when the designer studio ran (``all``: every engine was a target, as
with ``run --studio``). Version 1 headers (no ``files``) are still read; a reader ignores keys it
does not know.

Frame lines carry ``seq``, ``t`` (seconds from the session's first frame), ``pucks``,
``touches``, ``streams``, ``characters``, ``commands`` and ``focus``, with floats written exactly
(shortest repr round-trips). So that a replay feeds the engines exactly the times they had live,
the first frame of each file also carries ``t0`` (the session's first frame time, monotonic
seconds of the recording machine), and a frame whose monotonic time is not exactly ``t0 + t``
carries it as ``t_mono``. A frame where a filter took inputs away before the engines (the
studio: control-marker pucks and designer commands) carries them as ``consumed`` (see
:attr:`tabletop.frames.Frame.consumed`), so a replay runs the studio again; the frame whose
engines first play a hot-reloaded behaviour carries what it was trained from as
``consumed["reload"]["behaviors"]``, and one where a reload failed its label's note as
``consumed["reload"]["notes"]`` (:mod:`tabletop.studio.reloader`), and one whose MOP
characters first follow an action as a kiosk read it on disk (fixed after a start without it,
or replaced later) the files it was read from as ``consumed["reload"]["actions"]``
(:mod:`tabletop.kiosk.actions`), and one whose studio first follows a MOP character's or
touch-pose engine's library files, or a Puppet Master library's listing, changed on disk those
files as ``consumed["reload"]["libraries"]`` (:class:`tabletop.studio.reloader.LibraryReloads`).
A reader accepts a file whose last line was cut short by a power cut.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import math
from pathlib import Path
from typing import Any, Callable, Iterator, TypeVar

import numpy as np

from tabletop import __version__
from tabletop.frames import MAX_POSITION_M, CharacterState, Frame, InputError, Puck, Touch

log = logging.getLogger("tabletop")

FORMAT = "tabletop-session"
VERSION = 2
READABLE = (1, 2)
RELOADS = ("behaviors", "notes", "actions", "libraries")
"""What a frame's ``consumed["reload"]`` may hold (see the module docstring)."""
MAX_T = 1e8   # seconds (three years): a larger recorded time is damage, not a session
MAX_SPEED = 1e6   # m/s or rad/s: no puck or finger crosses a 1000 m table in a millisecond
T = TypeVar("T")


class SessionError(InputError):
    """A session recording is missing or malformed; names the file and line."""


def _num(v: float) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def _unnum(v: Any, what: str = "value") -> float:
    """A recorded optional number (null: NaN) as a float; ValueError naming ``what``."""
    return math.nan if v is None else _finite(v, what)


def frame_to_dict(frame: Frame, t0: float = 0.0) -> dict[str, Any]:
    """A JSON-able dict of the frame with its time made relative to ``t0``."""
    return {
        "seq": frame.seq,
        "t": frame.t - t0,
        "pucks": [_puck_to_dict(p) for p in frame.pucks],
        "touches": [{"id": c.id, "x": c.x, "y": c.y, "vx": c.vx, "vy": c.vy}
                    for c in frame.touches],
        "streams": {k: v.tolist() for k, v in frame.streams.items()},
        "characters": [_character_to_dict(c) for c in frame.characters],
        "commands": list(frame.commands),
        **({"focus": frame.focus} if frame.focus is not None else {}),
        **({"consumed": {k: {"pucks": [_puck_to_dict(p) for p in v.get("pucks", ())],
                             "commands": list(v.get("commands", ())),
                             **{r: v[r] for r in RELOADS if r in v}}
                         for k, v in frame.consumed.items()}} if frame.consumed else {}),
    }


def _puck_to_dict(p: Puck) -> dict[str, Any]:
    return {"id": p.id, "x": p.x, "y": p.y, "angle": p.angle, "vx": p.vx, "vy": p.vy,
            "omega": p.omega, "state": p.state, "raw_x": _num(p.raw_x),
            "raw_y": _num(p.raw_y), "raw_angle": _num(p.raw_angle)}


def _puck_from_dict(p: dict[str, Any]) -> Puck:
    return Puck(_whole(p["id"], "puck id"), _position(p["x"], "x"), _position(p["y"], "y"),
                _finite(p["angle"], "angle"), _speed(p.get("vx", 0.0), "vx"),
                _speed(p.get("vy", 0.0), "vy"), _speed(p.get("omega", 0.0), "omega"),
                str(p.get("state", "seen")), _unnum(p.get("raw_x"), "raw_x"),
                _unnum(p.get("raw_y"), "raw_y"), _unnum(p.get("raw_angle"), "raw_angle"))


def _commands(value: Any, what: str) -> tuple[str, ...]:
    if not isinstance(value, (list, tuple)) or not all(isinstance(c, str) for c in value):
        raise ValueError(f"{what}: expected a list of strings")
    return tuple(value)


def consumed_from_dict(value: Any) -> dict[str, dict[str, Any]]:
    """``consumed`` of a frame line: by filter, the pucks and commands it took (and the hot
    reloads' ``behaviors`` and failed reloads' ``notes``)."""
    if not isinstance(value, dict) or not all(isinstance(v, dict) for v in value.values()):
        raise ValueError("consumed: expected a mapping of filters to {pucks, commands}")
    out: dict[str, dict[str, Any]] = {}
    for k, v in value.items():
        out[str(k)] = {"pucks": _each(v.get("pucks", []), f"consumed.{k}.pucks", _puck_from_dict),
                       "commands": _commands(v.get("commands", []), f"consumed.{k}.commands")}
        if "behaviors" in v:      # a hot reload: {engine: what it trained from}
            if not isinstance(v["behaviors"], dict) or not all(
                    isinstance(b, dict) for b in v["behaviors"].values()):
                raise ValueError(f"consumed.{k}.behaviors: expected a mapping of engines to "
                                 "{name, parameters, shape, demonstration}")
            out[str(k)]["behaviors"] = v["behaviors"]
        if "notes" in v:          # a failed hot reload: {engine: its label's note}
            if not isinstance(v["notes"], dict) or not all(
                    isinstance(n, str) for n in v["notes"].values()):
                raise ValueError(f"consumed.{k}.notes: expected a mapping of engines to notes")
            out[str(k)]["notes"] = v["notes"]
        if "actions" in v:        # MOP actions followed once fixed: {engine: [{character,
            actions = v["actions"]  # action, files}]} (tabletop.kiosk.actions)
            if not isinstance(actions, dict) or not all(
                    isinstance(e, list) and all(isinstance(a, dict) and isinstance(
                        a.get("files"), list) for a in e) for e in actions.values()):
                raise ValueError(f"consumed.{k}.actions: expected a mapping of engines to "
                                 "lists of {character, action, files}")
            out[str(k)]["actions"] = actions
        if "libraries" in v:      # studio library files reloaded: {target: {name: base64}}
            libs = v["libraries"]
            if not isinstance(libs, dict) or not all(
                    isinstance(f, dict) and all(isinstance(b, str) for b in f.values())
                    for f in libs.values()):
                raise ValueError(f"consumed.{k}.libraries: expected a mapping of studio "
                                 "targets to {file name: base64}")
            out[str(k)]["libraries"] = libs
    return out


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


def _finite(v: Any, what: str) -> float:
    """``v`` as a finite float; ValueError naming ``what`` (a frame field) when it is not."""
    try:
        x = float(v)
    except (TypeError, ValueError):
        x = math.nan        # 'far', a list: said like NaN, with the field's name
    if isinstance(v, bool) or not math.isfinite(x):
        raise ValueError(f"{what} is {v!r}, expected a finite number")
    return x


def _position(v: Any, what: str) -> float:
    """A puck's or touch's table coordinate, metres, within ``frames.MAX_POSITION_M`` (a puck
    at x = 1e300 replayed through every engine, and the TUIO sink failed on every frame: it
    does not fit an OSC float)."""
    x = _finite(v, what)
    if abs(x) > MAX_POSITION_M:
        raise ValueError(f"{what} is {v!r} m, beyond {MAX_POSITION_M:g} m of the table")
    return x


def _speed(v: Any, what: str) -> float:
    """A velocity (m/s, or rad/s for omega) within MAX_SPEED."""
    x = _finite(v, what)
    if abs(x) > MAX_SPEED:
        raise ValueError(f"{what} is {v!r} per second, beyond {MAX_SPEED:g}")
    return x


def _vector(v: Any, what: str) -> np.ndarray:
    """A list of finite numbers as a float array; ValueError naming ``what`` otherwise."""
    if not isinstance(v, list):
        raise ValueError(f"{what}: expected a list of numbers")
    return np.array([_finite(x, what) for x in v], dtype=float)


def _whole(v: Any, what: str) -> int:
    """``v`` as an int (an id); ValueError naming ``what`` when it is no whole number."""
    if isinstance(v, bool) or not isinstance(v, int):
        raise ValueError(f"{what} is {v!r}, expected a whole number")
    return v


def _each(items: Any, what: str, parse: Callable[[dict[str, Any]], T]) -> tuple[T, ...]:
    """``parse`` of every object of the frame's list ``what`` (``pucks``, ``touches``, ...);
    ValueError naming ``what`` when it is no list of objects or an object lacks a key (a
    recording damaged by hand or by another program: said in its terms, not Python's)."""
    if not isinstance(items, list) or not all(isinstance(x, dict) for x in items):
        raise ValueError(f"{what}: expected a list of objects")
    out = []
    for i, item in enumerate(items):
        try:
            out.append(parse(item))
        except KeyError as exc:
            raise ValueError(f"{what}[{i}]: missing {exc}") from None
    return tuple(out)


def _touch_from_dict(c: dict[str, Any]) -> Touch:
    return Touch(_whole(c["id"], "touch id"), _position(c["x"], "x"), _position(c["y"], "y"),
                 _speed(c.get("vx", 0.0), "vx"), _speed(c.get("vy", 0.0), "vy"))


def _numbers(v: Any, what: str, check: Callable[[Any, str], Any], depth: int = 1) -> Any:
    """A recorded list (``depth`` 1) or list of lists (2) whose every item passes ``check``
    (:func:`_finite`, :func:`_whole`), as it was recorded; ValueError naming ``what``."""
    if not isinstance(v, list):
        raise ValueError(f"{what}: expected a list" + (" of lists" if depth > 1 else "")
                         + " of numbers")
    for x in v:
        _numbers(x, what, check, depth - 1) if depth > 1 else check(x, what)
    return v


def _character_from_dict(c: dict[str, Any]) -> CharacterState:
    points = c.get("points")
    if points is not None:
        if any(len(xy) != 2 for xy in _numbers(points, "character points", _finite, 2)):
            raise ValueError("character points: expected a list of [x, y]")
        points = np.asarray(points, float).reshape(-1, 2)
    color = _numbers(c.get("color", [240, 170, 60]), "character color", _finite)
    if len(color) != 3:
        raise ValueError("character color: expected [r, g, b]")
    bones = _numbers(c.get("bones", []), "character bones", _whole, 2)
    if any(len(b) != 2 for b in bones):
        raise ValueError("character bones: expected a list of [i, j]")
    return CharacterState(
        str(c["name"]), _finite(c["x"], "x"), _finite(c["y"], "y"),
        _finite(c["heading"], "heading"), kind=str(c.get("kind", "reactor")),
        size=_finite(c.get("size", 0.08), "size"),
        color=tuple(color),
        points=points,
        bones=tuple(map(tuple, bones)),
        progress=None if "progress" not in c else _unnum(c["progress"], "progress"),
        action=c.get("action"), valid=bool(c.get("valid", True)), label=str(c.get("label", "")))


def frame_from_dict(d: dict[str, Any]) -> Frame:
    """Inverse of :func:`frame_to_dict` (times stay relative to the recording's start)."""
    if not isinstance(d, dict):
        raise TypeError("expected a JSON object")
    pucks = _each(d.get("pucks", []), "pucks", _puck_from_dict)
    touches = _each(d.get("touches", []), "touches", _touch_from_dict)
    streams = d.get("streams", {})
    if not isinstance(streams, dict):
        raise ValueError("streams: expected a mapping of names to lists of numbers")
    streams = {str(k): _vector(v, f"streams.{k}") for k, v in streams.items()}
    characters = _each(d.get("characters", []), "characters", _character_from_dict)
    commands = _commands(d.get("commands", ()), "commands")
    consumed = consumed_from_dict(d["consumed"]) if "consumed" in d else {}
    focus = d.get("focus")
    if focus is not None and not isinstance(focus, str):
        raise ValueError("focus: expected a string")
    seq = d["seq"]
    if isinstance(seq, bool) or not isinstance(seq, int) or seq < 0:
        raise ValueError(f"seq is {seq!r}, expected a whole number >= 0")
    t = _finite(d["t"], "t")
    if abs(t) > MAX_T:
        raise ValueError(f"t is {d['t']!r} s, beyond {MAX_T:g} s")
    return Frame(seq=seq, t=t, pucks=pucks, touches=touches, streams=streams,
                 characters=characters, commands=commands, focus=focus, consumed=consumed)


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


def session_header(config: Any, calibration: dict[str, Any] | None = None,
                   **extra: Any) -> dict[str, Any]:
    """The header of a recording of an installation built from ``config``: a validated
    :class:`tabletop.config.Config` is carried as written with its files embedded; any other
    mapping is written as it is."""
    from tabletop.bundle import portable
    raw, refs = getattr(config, "raw", None), getattr(config, "refs", None)
    if raw is not None and refs is not None:
        written, files, external = portable(raw, refs)
    else:
        written, files, external = config or {}, {}, []
    header = {"format": FORMAT, "version": VERSION, "tabletop": __version__,
              "config_file": getattr(config, "file", None), "config": jsonable(written),
              "files": files, "calibration": jsonable(calibration)}
    if external:
        header["external"] = external
    header.update(extra)
    return header


def _lines(p: Path) -> Iterator[tuple[int, bytes]]:
    try:
        with open(p, "rb") as f:
            yield from enumerate(f, start=1)
    except FileNotFoundError:
        raise SessionError(f"{p}: session recording not found") from None
    except IsADirectoryError:
        raise SessionError(f"{p}: is a folder, expected a session recording (.jsonl)") from None
    except OSError as exc:
        raise SessionError(f"{p}: cannot read session recording: {exc.strerror or exc}") from None


def _json(p: Path, n: int, raw: bytes) -> Any:
    try:
        return json.loads(raw.decode("utf-8"))
    except UnicodeDecodeError:
        raise SessionError(f"{p}: line {n}: not UTF-8 text (a binary or damaged line)") from None
    except (json.JSONDecodeError, RecursionError, ValueError) as exc:
        msg = getattr(exc, "msg", None) or type(exc).__name__
        raise SessionError(f"{p}: line {n}: not valid JSON ({msg})") from None


def read_header(path: str | Path) -> dict[str, Any]:
    """The header of a session file; raises SessionError if it is not one."""
    p = Path(path)
    first = next(_lines(p), None)
    if first is None or not first[1].strip():
        raise SessionError(f"{p}: empty file; expected a {FORMAT} header line")
    try:
        header = _json(p, 1, first[1])
    except SessionError as exc:
        if first[1].startswith(b'{"format":"%s"' % FORMAT.encode()) and not \
                first[1].endswith(b"\n"):   # (JSON's own words were "Unterminated string")
            raise SessionError(f"{p}: line 1: its header is cut short (the recording was "
                               "interrupted while it was written): nothing to replay") from None
        raise SessionError(f"{exc} (expected a {FORMAT} header)") from None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        if isinstance(header, dict) and {"target", "outcome"} <= header.keys():
            raise SessionError(f"{p}: a studio session log (its tries: `tabletop review` "
                               "draws them), not a session recording (`tabletop run "
                               "--record FILE` makes one)")
        raise SessionError(f"{p}: line 1: not a {FORMAT} header")
    if header.get("version") not in READABLE:
        raise SessionError(f"{p}: line 1: version {header.get('version')!r} is not supported "
                           f"(this tabletop reads versions {', '.join(map(str, READABLE))})")
    for key, kind in (("config", dict), ("files", dict), ("calibration", dict)):
        if header.get(key) is not None and not isinstance(header[key], kind):
            raise SessionError(f"{p}: line 1: {key}: expected a mapping")
    return header


def read_frames(path: str | Path, absolute: bool = False) -> Iterator[Frame]:
    """The frames of a session file, in order. A malformed line, or a time that is not a finite
    number or goes backwards, raises SessionError naming it; a cut-short last line is skipped
    with a warning, blank lines after the last frame are left alone. With ``absolute`` each
    frame has the monotonic time it had live (as the engines saw it), else seconds from the
    session's first frame."""
    p = Path(path)
    read_header(p)
    state = {"t0": None, "last": -math.inf}
    lines = _lines(p)
    next(lines)
    pending: tuple[int, bytes] | None = None
    blank: int | None = None   # the first of the blank lines since the last frame
    for item in lines:
        if not item[1].strip():   # blank lines after the last frame (an editor's) are no frame
            blank = item[0] if blank is None else blank
            continue
        if blank is not None:
            raise SessionError(f"{p}: line {blank}: a blank line between frames (only the end "
                               "of a recording may have blank lines)")
        if pending is not None:
            yield _parse_line(p, *pending, state, absolute)
        pending = item
    if pending is not None:
        n, raw = pending
        if not raw.endswith(b"\n"):
            try:
                frame = _parse_line(p, n, raw, state, absolute)
            except SessionError:
                log.warning("%s: line %d is cut short (the recording was interrupted); "
                            "skipped", p, n)
                return
            yield frame
        else:
            yield _parse_line(p, n, raw, state, absolute)


def _parse_line(p: Path, n: int, raw: bytes, state: dict, absolute: bool) -> Frame:
    d = _json(p, n, raw)
    try:
        frame = frame_from_dict(d)
        if "t0" in d:
            state["t0"] = _finite(d["t0"], "t0")
        t_mono = None if d.get("t_mono") is None else _finite(d["t_mono"], "t_mono")
    except (KeyError, TypeError, ValueError, OverflowError) as exc:
        what = f"missing {exc}" if isinstance(exc, KeyError) else str(exc)
        raise SessionError(f"{p}: line {n}: not a valid frame ({what})") from None
    if frame.t < state["last"]:
        raise SessionError(f"{p}: line {n}: t {frame.t!r} goes back in time (the previous "
                           f"frame's is {state['last']!r})")
    state["last"] = frame.t
    if not absolute:
        return frame
    if t_mono is not None:
        t = t_mono
    elif state["t0"] is not None:
        t = state["t0"] + frame.t
    else:
        t = frame.t
    return dataclasses.replace(frame, t=t)
