"""The studio's indicator: the one ``kind="studio"`` character the view draws as the countdown,
the recording mark and the status line (what the machine of :mod:`tabletop.studio.machine` is
doing, and what the designer may do next)."""

from __future__ import annotations

from typing import Any

from tabletop.frames import CharacterState, Frame


def indicator(studio: Any, frame: Frame) -> CharacterState:
    """The indicator of ``studio`` (a :class:`~tabletop.studio.machine.Studio`, which imports
    this module): ``action`` = state, ``progress`` = countdown left (s) or recorded seconds,
    ``label`` = status line; ``action`` "quiet": a line for the operator overlay alone (the
    studio draws nothing until a designer key but the messages said to it)."""
    target = studio.target
    if studio.quiet and studio._t < studio._message_until:
        # a message said to the designer (a library item changed elsewhere, a kiosk's config
        # edit on the takes): on the table for its seconds all the same, alone (no key line)
        return CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0,
                              color=(255, 60, 60), action="idle", valid=True,
                              label=f"[{studio.selected or '-'}] {studio.message}")
    if studio.quiet:
        # nothing on the table until a designer key; a library file gone bad (edited by hand)
        # is on the operator overlay all the same: it was in the log alone
        said = (f"{len(studio.problems)} bad library file(s): {studio.problems[0]}"
                if studio.problems else "")
        return CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0,
                              action="quiet" if said else "idle", label=said)
    points = None
    if studio.state == "countdown":
        value: float | None = max(0.0, studio.until - frame.t)
    elif studio.state == "recording" and target is not None:
        value = target.seconds()
    else:
        value = None
    if studio.state == "trying" and target is not None and hasattr(target, "guide"):
        points = target.guide()       # where to try it (table metres), drawn as a path
    warning = studio._warning if studio._t < studio._warning_until else ""
    if studio._t < studio._message_until:
        text = f"{warning}   | {studio.message}" if warning else studio.message
    elif warning:
        text = warning
    elif target is None:
        text = "no designer target"
    else:
        name = getattr(target, "shown", target.current)()
        text = {"idle": f"{target.what} {name or '(none)'}: R record, "
                        "[ ] switch, F2 rename, Del delete, U undo",
                "countdown": getattr(target, "cue", "get ready"),
                "recording": f"recording{' ' + studio._part if studio._part else ''}: R stop",
                "ready": f"R records {studio._part}, X cancels",
                "training": "training the take...",
                "trying": "try it: K keep, X discard, R redo"}[studio.state]
    if studio.problems:
        text += f"   | {len(studio.problems)} bad library file(s): {studio.problems[0]}"
    return CharacterState("studio", 0.0, 0.0, 0.0, kind="studio", size=0.0,
                          color=(255, 60, 60), progress=value, action=studio.state,
                          label=f"[{studio.selected or '-'}] {text}", valid=True,
                          points=points)
