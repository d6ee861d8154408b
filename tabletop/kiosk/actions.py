"""MOP actions a kiosk started without, followed once their files are fixed on disk.

A kiosk's start (or a config edit's rebuild) runs a MOP character without each configured
action whose template or clip file cannot be read (:func:`tabletop.plugins.mop_files.
configured_actions`: the stage's ``missing``, each listed in the status's ``behavior_errors``).
:class:`ActionReloader`, a frame filter, looks at those files' modification times and sizes
once a second (``os.stat`` only; nothing is read while they stay as they were, nothing at all
once every action is followed); once they changed and then stayed as they were for a whole look
it reads the action again and, if it reads, gives it to its character (:meth:`MopStage.
put_action`: the followers retrained within that tick) and drops its error. A file still bad is
said once per new reason. (Read at the first look that saw a change, a template copied in two
writes with a look between was followed with its first half, a valid CSV, and its completion
never read: a followed action's files are not looked at again.)

The frame whose engines first follow the action holds the bytes it was read from
(``consumed["reload"]["actions"]``), and a replay reads the action from them within that frame
(:func:`replay_actions`), so it follows it from the same tick.
"""

from __future__ import annotations

import base64
import dataclasses
import logging
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

from tabletop.frames import Frame, InputError
from tabletop.kiosk.watch import Poller, tree_signature

log = logging.getLogger("tabletop")

LOOK_S = 1.0
"""Seconds (wall clock) between looks at a missing action's files, as at the config file."""


def _signature(files: tuple[Path, ...]) -> Callable[[Path], tuple]:
    return lambda _path: tuple(map(tree_signature, files))


def _read(files: tuple[Path, ...]) -> list[bytes] | None:
    try:
        return [f.read_bytes() for f in files]
    except OSError:
        return None


def _took(stage: Any, missing: dict[str, Any], taken: tuple) -> None:
    """``stage`` follows the action ``missing`` names from now on: out of its missing ones and
    of its errors."""
    action, performer, samples = taken
    stage.put_action(missing["character"]["name"], action, performer, samples)
    stage.missing.remove(missing)
    if missing["why"] in stage.start_problems:
        stage.start_problems.remove(missing["why"])


class ActionReloader:
    """Frame filter of a MOP ``stage`` with missing actions (see the module docstring)."""

    def __init__(self, stage: Any, every_s: float = LOOK_S,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.stage = stage
        self.pollers = {id(m): Poller(m["files"][0], every_s, clock, read=m["read"],
                                      signature=_signature(m["files"]), settle=True)
                        for m in stage.missing}

    def __call__(self, frame: Frame | None = None) -> Frame | None:
        taken = []
        for m in list(self.stage.missing):
            poller = self.pollers.get(id(m))
            if poller is None or not poller.changed():
                continue
            entry = self._try(m)
            if entry is None:
                continue
            if entry is False:      # written while it was read: the next look reads it again
                poller.signature = None
                continue
            taken.append(entry)
        if not taken or frame is None:
            return frame
        reload = frame.consumed.get("reload", {})
        actions = {**reload.get("actions", {}), self.stage.name: taken}
        return dataclasses.replace(frame, consumed={**frame.consumed,
                                                    "reload": {**reload, "actions": actions}})

    def _try(self, m: dict[str, Any]) -> dict[str, Any] | None | bool:
        """Read the action ``m`` again: its record (followed from now), None (still bad,
        said once per reason) or False (its files changed while read)."""
        c, a = m["character"], m["action"]
        before = _read(m["files"])
        try:
            taken = self.stage.configured_action(c, a)
        except InputError as exc:
            why = f"character {c['name']!r}, action {a['name']!r}: {exc}"
            if why != m["why"]:
                log.error("MOP action still not followed: %s", why)
                problems = self.stage.start_problems
                if m["why"] in problems:
                    problems[problems.index(m["why"])] = why
                m["why"] = why
            return None
        if before is None or _read(m["files"]) != before:
            return False
        _took(self.stage, m, taken)
        log.info("MOP character %r follows its action %r from now on: %s read", c["name"],
                 a["name"], ", ".join(map(str, m["files"])))
        return {"character": c["name"], "action": a["name"],
                "files": [base64.b64encode(b).decode("ascii") for b in before]}


def replay_actions(stage: Any, entries: list[dict[str, Any]]) -> None:
    """A replay's frame whose live run followed missing actions again (``entries``, recorded
    by :class:`ActionReloader`): each is read from its recorded bytes (written into a folder
    of its own, under its files' names) and followed from this frame. One that cannot be is
    logged and skipped."""
    for entry in entries:
        m = next((m for m in getattr(stage, "missing", ()) if
                  m["character"]["name"] == entry.get("character")
                  and m["action"]["name"] == entry.get("action")), None)
        if m is None:
            log.error("replay: recorded action %r of %r is not one %s started without; skipped",
                      entry.get("action"), entry.get("character"), stage.name)
            continue
        c, a = m["character"], m["action"]
        try:
            with tempfile.TemporaryDirectory(prefix="tabletop-action-") as tmp:
                paths = []
                for k, (f, data) in enumerate(zip(m["files"], entry["files"])):
                    p = Path(tmp) / str(k) / f.name
                    p.parent.mkdir()
                    p.write_bytes(base64.b64decode(data, validate=True))
                    paths.append(p)
                moved = dict(a, template=str(paths[0]))
                if len(paths) > 1:
                    moved["motion"] = str(paths[1])
                taken = stage.configured_action(c, moved)
        except (InputError, KeyError, TypeError, ValueError, OSError) as exc:
            log.error("replay: recorded action %r of %r not read: %s", a["name"], c["name"], exc)
            continue
        _took(stage, m, taken)
