"""Recording parts that replay on their own: what a later part's header carries.

A recording continues in a new part (``max_mb`` reached, a resume after a full disk) with its
own header line (:func:`header_line`), which carries what a replay of that part alone needs
from the frames before it: ``reloaded``, what the session reloaded so far (:func:`carried`;
played at the part's first frame, :func:`with_reloaded`), and ``performers``, its engines'
states before its first frame (:func:`part_states`; its engines go on from them,
:func:`resume_parts`). The file format itself: :mod:`tabletop.session`.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
from typing import Any

from tabletop.frames import Frame
from tabletop.session import FORMAT, RELOADS, VERSION, consumed_from_dict


def carried(state: dict[str, Any], reload: dict[str, Any] | None) -> dict[str, Any]:
    """``state`` (a part header's ``reloaded``: what the frames so far reloaded, as one
    frame's ``consumed["reload"]`` that plays it all again) with a frame's ``reload`` taken
    in: each engine's latest behaviour, its latest note unless a later behaviour cleared it,
    each MOP action's latest read, each studio target's latest library files (a library
    listing's latest file by file)."""
    if not reload:
        return state
    out = {k: dict(v) for k, v in state.items()}
    for name, source in reload.get("behaviors", {}).items():
        out.setdefault("behaviors", {})[name] = source
        out.get("notes", {}).pop(name, None)     # (RecordedReloads clears it, then notes)
    out.setdefault("notes", {}).update(reload.get("notes", {}))
    for name, files in reload.get("libraries", {}).items():   # a listing: its changed files
        libs = out.setdefault("libraries", {})
        libs[name] = {**libs.get(name, {}), **files} if name.endswith(" library") else files
    for name, entries in reload.get("actions", {}).items():   # each action's latest read
        def key(e: Any) -> tuple:
            return (e.get("character"), e.get("action")) if isinstance(e, dict) else (id(e),)
        latest = {key(e) for e in entries}
        out.setdefault("actions", {})[name] = [
            *(e for e in out.get("actions", {}).get(name, []) if key(e) not in latest),
            *entries]
    return {k: v for k, v in out.items() if v}


def part_states(engines: Any) -> dict[str, Any]:
    """Each engine's state that a later recording part carries (its ``part_state()``: a MOP
    stage's performers, where their gestures started and whether they rest), by name, for
    the recorder to take after every frame (about 5 us with one puck performer)."""
    return {e.name: s for e in engines
            if (f := getattr(e, "part_state", None)) is not None and (s := f())}


def resume_parts(engines: Any, states: Any) -> None:
    """The ``engines`` of a part replayed alone go on from the ``states`` its header carries
    (:func:`part_states`); ValueError (KeyError, TypeError) names what is wrong."""
    if not isinstance(states, dict):
        raise ValueError("expected a mapping of engines to their states")
    for e in engines:
        if e.name in states and hasattr(e, "resume_part"):
            try:
                e.resume_part(states[e.name])
            except (KeyError, TypeError, ValueError) as exc:
                raise ValueError(f"engine {e.name!r}: {exc}") from None


def with_reloaded(frame: Frame, reloaded: Any) -> Frame:
    """A part's first ``frame`` playing its header's ``reloaded`` (:func:`carried`) before its
    own reloads: a later part replayed on its own starts with the behaviours, actions and
    library files the live run had reloaded by then (its header's files are the session's
    start's). A ``reloaded`` that is not one is refused, ValueError naming its key (said as
    the header's, not as the frame's ``consumed.reload`` it is read as)."""
    if not reloaded:
        return frame
    if not isinstance(reloaded, dict):
        raise ValueError(f"expected a mapping of {', '.join(RELOADS)}")
    try:
        state = consumed_from_dict({"reload": reloaded})["reload"]
    except ValueError as exc:
        raise ValueError(str(exc).removeprefix("consumed.reload.")) from None
    state = {k: v for k, v in state.items() if k in RELOADS}
    merged = carried(state, frame.consumed.get("reload"))
    return dataclasses.replace(frame, consumed={**frame.consumed, "reload": merged})



def header_line(header: dict[str, Any], order: int, part: int, session: str,
                reloaded: dict[str, Any] | None = None,
                performers: dict[str, Any] | None = None) -> bytes:
    """The first line of a recording part: format, version, ``order`` first (see
    recordings.ORDER), its ``session`` (:func:`tabletop.recordings.new_session`), then ``header``,
    with this part's ``order``, ``session`` and ``part`` (not a copied header's: replay --out hands
    on the recording's own) and the time it is created; ``reloaded``: what the session reloaded
    before the part began (:func:`carried`), and ``performers``, its engines'
    states before its first frame (:func:`part_states`), so that it replays
    on its own; a first part keeps a copied header's ``performers``."""
    line = {"format": FORMAT, "version": VERSION, "order": order, "session": session}
    line.update(header, order=order, session=session, part=part,
                created=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"))
    line.pop("reloaded", None)           # (a copied header's: replay --out)
    # a later part's engines start from its own states; a first part from a copied header's
    # (replay PART --out X: X is part 1 of its own session and starts where PART did)
    states = performers if part > 1 else line.pop("performers", None)
    line.pop("performers", None)
    if reloaded:
        line["reloaded"] = reloaded
    if states:
        line["performers"] = states
    return (json.dumps(line, separators=(",", ":"), default=str) + "\n").encode()
