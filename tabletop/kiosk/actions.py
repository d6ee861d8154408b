"""MOP actions a kiosk follows on disk: those it started without, once their files are fixed,
and every configured action's later replacement or breakage.

A kiosk's start (or a config edit's rebuild) runs a MOP character without each configured
action whose template or clip file cannot be read (:func:`tabletop.plugins.mop_files.
configured_actions`: the stage's ``missing``, each listed in the status's ``behavior_errors``).
:class:`ActionReloader`, a frame filter, looks at every configured action's files (the stage's
``watched``: those too) once a second, their modification times and sizes (``os.stat`` only;
nothing is read while they stay as they were); once they changed and then stayed as they were
for a whole look it reads each file once (regular files only, capped:
:func:`tabletop.file_io.read_regular_bytes`, so a named pipe put there cannot hold the frame
loop), builds the action from those bytes and, if it builds, gives it to its character (a
missing one, or in place of the one it played) and drops its error; the actions taken in one
tick retrain the followers once (:meth:`MopStage.put_actions`). A file that does not build (made
unreadable, deleted, cut short) is said once per new reason and listed in ``behavior_errors``
(the stage's ``start_problems``) while the character plays the action as read before; a file
fixed or replaced after that is followed the same way. (A change is read only once the files
stayed as they were for a whole look: a template copied in two writes is not followed with its
first half, a valid CSV.) Files read to the bytes the action plays from (a ``touch``, an rsync
of the same bytes) are neither retrained nor recorded.

The frame whose engines first follow an action as read holds the bytes it was read from
(``consumed["reload"]["actions"]``), and a replay builds the action from them within that
frame (:func:`replay_actions`) as the live run did (:func:`_action_from`), so it follows it
from the same tick.
"""

from __future__ import annotations

import base64
import dataclasses
import logging
import os
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

from tabletop.files import UnreadableText, read_regular_bytes
from tabletop.frames import Frame, InputError
from tabletop.kiosk.watch import Poller, tree_signature

log = logging.getLogger("tabletop")

LOOK_S = 1.0
"""Seconds (wall clock) between looks at the actions' files, as at the config file."""

SCRATCH = "/dev/shm" if os.access("/dev/shm", os.W_OK | os.X_OK) else None
"""Where an action's bytes are written to be built from: in memory where the system has such a
folder. Making and removing the folder of a fix took 8 ms (median of 30, 2 kB written) in the
system's temporary folder on ext4, 0.08 ms in /dev/shm (tmpfs), on the frame loop's tick."""


def _signature(files: tuple[Path, ...]) -> Callable[[Path], tuple]:
    return lambda _path: tuple(map(tree_signature, files))


def _read(files: tuple[Path, ...], known: dict[Path, bytes | None] | None = None
          ) -> list[bytes | None]:
    """Each file's bytes, None for one that is not there (the action's build then says so as
    the start said it); InputError naming a file that cannot be read (not a regular file, too
    long, no permission). ``known``: files read already (each is read once into it)."""
    out: list[bytes | None] = []
    for f in files:
        if known is not None and f in known:
            out.append(known[f])
            continue
        try:
            out.append(read_regular_bytes(f))
            if known is not None:
                known[f] = out[-1]
        except FileNotFoundError:
            out.append(None)
        except UnreadableText as exc:
            raise InputError(f"{f}: {exc}") from None
        except OSError as exc:
            raise InputError(f"{f}: cannot read: {exc.strerror or exc}") from None
    return out


def _action_from(stage: Any, m: dict[str, Any], data: list[bytes | None]) -> tuple:
    """The watched action ``m`` built from ``data`` (its files' bytes, in the order of
    ``m["files"]``; None: not there), written into a folder of its own under the files' names;
    an InputError names the action's own files, as the start's messages do."""
    c, a = m["character"], m["action"]
    with tempfile.TemporaryDirectory(prefix="tabletop-action-", dir=SCRATCH) as tmp:
        paths = [Path(tmp) / str(k) / f.name for k, f in enumerate(m["files"])]
        for p, b in zip(paths, data):
            p.parent.mkdir()
            if b is not None:
                p.write_bytes(b)
        moved = dict(a, template=str(paths[0]))
        if len(paths) > 1:
            moved["motion"] = str(paths[1])
        try:
            return stage.configured_action(c, moved)
        except InputError as exc:
            text = str(exc)
            if len(paths) > 1:                   # (a clip named as the config names it)
                text = text.replace(repr(str(paths[1])), repr(a["motion"]))
            for p, f in zip(paths, m["files"]):
                text = text.replace(str(p), str(f))
            raise InputError(text) from None


def _take(stage: Any, taken: list[tuple[dict[str, Any], tuple]]) -> None:
    """``stage`` follows the actions taken (each: the watched entry, its action, performer and
    samples) from now on, the followers retrained once: out of its missing ones and of its
    errors."""
    stage.put_actions([(m["character"]["name"], *t) for m, t in taken])
    for m, _ in taken:
        _cleared(stage, m)


def _cleared(stage: Any, m: dict[str, Any]) -> None:
    """The watched entry ``m`` out of ``stage``'s missing ones and of its errors."""
    stage.missing[:] = [e for e in stage.missing if e is not m]
    if m["why"] in stage.start_problems:
        stage.start_problems.remove(m["why"])
    m["why"] = None


def _watched(stage: Any) -> list[dict[str, Any]]:
    """The entries of ``stage``'s configured actions (a stage built without them: its missing
    ones)."""
    return list(getattr(stage, "watched", None) or getattr(stage, "missing", ()))


class ActionReloader:
    """Frame filter of a MOP ``stage`` following its configured actions' files (see the
    module docstring)."""

    def __init__(self, stage: Any, every_s: float = LOOK_S,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """One look at every watched action's files each ``every_s`` s of ``clock``, all at
        the same tick: were each action's look due ``every_s`` after its own, the looks would
        drift apart by the time the ones before them took (a still-bad file read, a loaded
        machine), and the actions of one fixed file be followed from different frames."""
        self.stage, self.every_s, self.clock = stage, every_s, clock
        self._next = clock()
        self.watched = _watched(stage)
        self.pollers = {id(m): Poller(m["files"][0], 0.0, clock, read=m["read"] or None,
                                      signature=_signature(m["files"]), settle=True)
                        for m in self.watched}
        known: dict[Path, bytes | None] = {}    # each file read once, however many actions
        # name it (examples/mop.yaml: 16 template reads -> 6)
        for m in self.watched:      # the bytes each playing action was built from
            if m["why"] is None and m["read"]:
                try:
                    data = _read(m["files"], known)
                except InputError:
                    continue
                if _signature(m["files"])(m["files"][0]) == m["read"]:   # (as the start read)
                    m["data"] = data

    def __call__(self, frame: Frame | None = None) -> Frame | None:
        if not self.watched:
            return frame
        now = self.clock()
        if now < self._next:
            return frame
        self._next = now + self.every_s
        taken, records = [], []
        for m in self.watched:
            poller = self.pollers[id(m)]
            if not poller.changed():
                continue
            got = self._try(m, poller.signature)
            if got is None or got is True:
                continue
            if got is False:        # written while it was read: the next look reads it again
                poller.signature = None
                continue
            taken.append((m, got[0]))
            records.append(got[1])
        if taken:
            try:
                _take(self.stage, taken)
                for m, _ in taken:
                    m["data"] = m.pop("built")
            except Exception:       # (looked at again next time, not only once they change)
                for m, _ in taken:
                    self.pollers[id(m)].signature = None
                raise
        if not records or frame is None:
            return frame
        reload = frame.consumed.get("reload", {})
        actions = {**reload.get("actions", {}), self.stage.name: records}
        return dataclasses.replace(frame, consumed={**frame.consumed,
                                                    "reload": {**reload, "actions": actions}})

    def _try(self, m: dict[str, Any], looked: tuple | None
             ) -> tuple[tuple, dict[str, Any]] | None | bool:
        """Read the action ``m`` again (its files as they were at the look, signature
        ``looked``): its action and the frame's record of it, None (bad: said once per
        reason, listed while it stays so), False (its files changed while read) or True (the
        bytes it plays from: a ``touch``, an rsync or a deploy copying the same bytes is
        neither retrained, 15-70 ms on the frame loop, nor recorded)."""
        c, a = m["character"], m["action"]
        try:
            data = _read(m["files"])
            if _signature(m["files"])(m["files"][0]) != looked:
                return False
            if data == m.get("data"):
                if m["why"] is not None:
                    log.info("MOP character %r plays its action %r as read before: %s "
                             "readable again, unchanged", c["name"], a["name"],
                             ", ".join(map(str, m["files"])))
                    _cleared(self.stage, m)
                return True
            taken = _action_from(self.stage, m, data)
        except (InputError, OSError) as exc:     # (OSError: the folder the bytes go into)
            why = f"character {c['name']!r}, action {a['name']!r}: {exc}"
            if why != m["why"]:
                if any(e is m for e in self.stage.missing):
                    log.error("MOP action still not followed: %s", why)
                else:
                    log.error("MOP action's file went bad, the character plays it as read "
                              "before: %s", why)
                problems = self.stage.start_problems
                if m["why"] in problems:
                    problems[problems.index(m["why"])] = why
                else:
                    problems.append(why)
                m["why"] = why
            return None
        log.info("MOP character %r follows its action %r from now on: %s read", c["name"],
                 a["name"], ", ".join(map(str, m["files"])))
        m["built"] = data           # (its ``data`` once the stage takes it)
        return taken, {"character": c["name"], "action": a["name"],
                       "files": [base64.b64encode(b or b"").decode("ascii") for b in data]}


def replay_actions(stage: Any, entries: list[dict[str, Any]]) -> None:
    """A replay's frame whose live run followed actions as read on disk (``entries``, recorded
    by :class:`ActionReloader`): each is built from its recorded bytes as the live run built
    it (:func:`_action_from`) and followed from this frame, the followers retrained once. One
    that cannot be (a damaged entry: not the number of files its action reads, bytes that are
    not base64) is logged in one line and skipped."""
    taken = []
    for entry in entries:
        entry = entry if isinstance(entry, dict) else {}
        m = next((m for m in _watched(stage) if
                  m["character"]["name"] == entry.get("character")
                  and m["action"]["name"] == entry.get("action")), None)
        if m is None:
            log.error("replay: recorded action %r of %r is not one %s configures; skipped",
                      entry.get("action"), entry.get("character"), stage.name)
            continue
        c, a, files = m["character"], m["action"], entry.get("files")
        if not isinstance(files, list) or len(files) != len(m["files"]) \
                or not all(isinstance(f, str) for f in files):
            log.error("replay: recorded action %r of %r skipped: its entry holds %s, expected "
                      "the bytes of its %d file(s) (%s)", a["name"], c["name"],
                      f"{len(files)} file(s)" if isinstance(files, list) else repr(files),
                      len(m["files"]), ", ".join(f.name for f in m["files"]))
            continue
        try:
            data = [base64.b64decode(f, validate=True) for f in files]
            taken.append((m, _action_from(stage, m, list(data))))
        except (InputError, ValueError, OSError) as exc:
            log.error("replay: recorded action %r of %r not read: %s", a["name"], c["name"], exc)
    if taken:
        _take(stage, taken)
