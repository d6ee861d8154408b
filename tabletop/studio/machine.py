"""The studio's state machine, shared by every engine through :class:`Target`.

States: ``idle`` -> (record) ``countdown`` -> ``recording`` -> (stop: trained at once) ``trying``
-> keep (saved to the library, named) | discard | redo (a new countdown) -> ``idle``.
A take in parts (Puppet Master's sequential training: the main, then the reaction against its
playback) waits in ``ready`` between its parts: record starts the next part's countdown; a part
may also end by itself (the playback's end). A target that trains in a worker thread leaves the
machine in ``training``; meanwhile the previous behaviour plays on. The new take is swapped in
between ticks, at the first tick ``swap_s`` (frame time) after the stop, waiting there for the
worker only if it is not done yet: the tick it plays from depends on the frames alone, so a
recorded session replays exactly.
Commands (keys through the view, control markers through :class:`Markers`):

=========================  =========================================================
``designer.record``        idle/trying/training: countdown then record (redo); ready: the
                           next part; recording: stop
``designer.stop``          stop recording (or cancel the countdown)
``designer.keep``          keep the take being tried
``designer.discard``       drop it, back to what played before
``designer.redo``          drop it and record again
``designer.assign``        the target's own choice (MOP: the motion a take plays)
``designer.window:+``      MOP: the character's follower window a step wider (``:-`` narrower),
                           idle or trying; saved with the character
``designer.item_next``     play the next (``item_previous``: previous) library item (not mid-take,
                           nor while a take is tried)
``designer.rename:NEW``    rename the item in play (``:OLD=NEW``, as F2 sends it: only while
                           OLD is in play)
``designer.delete``        delete the item in play (kept in the library's ``.trash``)
``designer.undo``          undo the last keep, rename or delete of any target (these three, as the
                           switch, not while a take is under way or tried)
``designer.only_target``   Tab with one designer target (:class:`~tabletop.loop.DesignerFocus`
                           sends it): said, so that the key is not taken for broken
=========================  =========================================================

The machine is a frame filter: it runs before the engines, takes the ``designer.*`` commands
for itself and adds one ``kind="studio"`` character that the view draws as the countdown, the
recording indicator and the status line. The commands on the library item in play (switch,
rename, delete, undo) are :class:`~tabletop.studio.library_commands.LibraryCommands`.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from pathlib import Path
from typing import Callable, Sequence

from tabletop.frames import CharacterState, Frame, InputError
from tabletop.studio.library_commands import LibraryCommands, Undo
from tabletop.studio.status import indicator
from tabletop.studio.take import Target, Try

log = logging.getLogger("tabletop")

MESSAGE_S = 5.0
SWAP_S = 0.15   # a take trained in a worker plays this long after the stop (frame time): a
                # minute's take trains in 15-95 ms here (bench/studio.py), so the loop rarely waits


class Studio(LibraryCommands):
    """Frame filter driving the focused :class:`Target`; see the module docstring."""

    def __init__(self, targets: Sequence[Target], countdown_s: float = 3.0,
                 log_try: Callable[[Try, Target], None] | None = None,
                 quiet: bool = False,
                 swap_s: float = SWAP_S) -> None:
        self.targets = {t.name: t for t in targets}
        self.order = [t.name for t in targets]
        self.countdown_s, self.log_try = countdown_s, log_try
        # saves a take tried at quit, (suffix, text) -> the file written (a SessionLog's)
        self.save_take: Callable[[str, str], str] | None = None
        self.state = "idle"
        self.selected: str | None = self.order[0] if self.order else None
        self.until = 0.0             # countdown end (frame time)
        self.message, self._message_until = "", -math.inf
        self._message_s = 0.0        # how long the message shows, from the tick that draws it
        # the state and target a message was said in (None: said this tick); it is shown while
        # they last, at most MESSAGE_S
        self._message_for: tuple[str, str | None] | None = None
        self._warning, self._warning_until = "", -math.inf   # a take's problem ("no puck 2")
        # the bad library files each target's engine logged as it started: the studio logs
        # only what changes after that (one line per bad file for the operator)
        self.problems: list[str] = [p for t in targets
                                    for p in getattr(t, "started_problems", ())]
        self.undo_stack: list[Undo] = []
        self.tries: list[Try] = []
        self._try: Try | None = None
        self._part = ""              # the take's next part while "ready" (and recording it)
        self._t0 = 0.0               # perf_counter at the stop, while "training"
        self.swap_s, self._swap_at = swap_s, 0.0   # the trained take plays from _swap_at
        self._t = 0.0
        self.quiet = quiet   # draws nothing until the first designer command (not in studio mode)

    # --- focus -------------------------------------------------------------------------------

    def designer_targets(self) -> tuple[str, ...]:
        return tuple(self.order)

    @property
    def target(self) -> Target | None:
        return self.targets.get(self.selected) if self.selected else None

    def say(self, text: str) -> None:
        self._show(text, MESSAGE_S)
        log.info("studio: %s", text)

    def _show(self, text: str, seconds: float) -> None:
        """``text`` on the status line for ``seconds`` from the tick that first draws it (one
        said before the first frame, as a kiosk's rebuilt studio says what its edit did, would
        be past at once on the loop's clock)."""
        self.message, self._message_s, self._message_until = text, seconds, math.inf
        self._message_for = None

    def _message_ends(self) -> None:
        """A message belongs to the state and target it was said in: a new state (the
        countdown after "R records ...") or another target (Tab) ends it."""
        now = (self.state, self.selected)
        if self._message_for is None:
            self._message_for, self._message_until = now, self._t + self._message_s
        elif self._message_for != now:
            self._message_until = -math.inf

    # --- the filter ----------------------------------------------------------------------------

    def __call__(self, frame: Frame) -> Frame:
        self._t = frame.t
        for target in self.targets.values():    # library picks trained in a worker swap in
            between = getattr(target, "between_ticks", None)
            if between is not None:
                between(frame.t)
        if frame.focus in self.targets and frame.focus != self.selected:
            left, tried = self.selected, self.state in ("trying", "training")
            if self.state != "idle":     # the take is left: dropped (logged once trained), said
                self._drop("discarded" if tried else "")
                self.say(f"{left}: take {'discarded' if tried else 'cancelled'} (Tab left it)")
            self.selected = frame.focus
            self.quiet = False   # Tab is a designer key: its line names the target picked
        if self.state == "training" and self.target is not None:
            self._poll_training(self.target)     # between ticks: the worker's take swaps in
        ours = frame.focus is None or frame.focus in self.targets   # else another engine's
        mine = [c for c in frame.commands
                if ours and c.startswith("designer.") and c != "designer.next"]
        for cmd in mine:
            self.command(cmd)
        target = self.target
        if target is not None:
            if self.state == "countdown" and frame.t >= self.until:
                if self._part:
                    target.resume(frame)
                else:
                    target.begin(frame)
                    self._try = Try(target.name, target.what, time.time())
                self.state = "recording"
            if self.state == "recording":
                problem = target.record(frame)
                if problem:     # beside a message said now (a refusal), not over it
                    self._warning, self._warning_until = problem, self._t + 0.2
                if target.ended():
                    self._stop(target, "")
        self._message_ends()
        rest = tuple(c for c in frame.commands if c not in mine)
        return dataclasses.replace(frame, commands=rest).with_characters((self.character(frame),))

    def command(self, cmd: str) -> None:
        self.quiet = False
        target = self.target
        if target is None:
            return
        name, _, arg = cmd.partition(":")
        try:
            getattr(self, "_" + name.removeprefix("designer."), self._unknown)(target, arg)
        except InputError as exc:
            self.say(f"cannot: {exc}")
        except OSError as exc:      # the library's folder went away or refuses: said, not raised
            self.say(f"cannot: {exc.filename or ''}: {exc.strerror or exc}")

    def _unknown(self, target: Target, arg: str) -> None: ...

    # --- the take ----------------------------------------------------------------------------

    def _record(self, target: Target, arg: str) -> None:
        if self.state == "recording":
            self._stop(target, arg)
        elif self.state == "countdown":
            self.state = "ready" if self._part else "idle"
            self.say("countdown cancelled")
        elif self.state == "ready":
            self.state, self.until = "countdown", self._t + self.countdown_s
        else:
            if self.state in ("trying", "training"):
                self._drop("redone")
            self.state, self.until = "countdown", self._t + self.countdown_s

    def _stop(self, target: Target, arg: str) -> None:
        if self.state == "countdown":     # (the record marker lifted, or hidden by a hand)
            self.state = "ready" if self._part else "idle"
            self.say("countdown cancelled")
            return
        if self.state != "recording":
            return
        self._warning_until = -math.inf   # a puck missing is of the recording, stopped now
        part = target.cut()
        if part:                         # the take goes on with another part
            self._part, self.state = part, "ready"
            self.say(f"R records {part}")
            return
        self._part = ""
        t = self._try or Try(target.name, target.what, time.time())
        t.duration_s = round(target.seconds(), 3)
        self._t0 = time.perf_counter()
        self._try = t
        try:
            summary = target.train()
        except InputError as exc:
            self._refused(t, exc)
            return
        if summary is None:       # a target may need longer (its own ``swap_s``)
            self.state = "training"
            self._swap_at = self._t + getattr(target, "swap_s", self.swap_s)
            return
        self._trained(t, summary)

    def _poll_training(self, target: Target) -> None:
        if self._t < self._swap_at:
            return
        t = self._try or Try(target.name, target.what, time.time())
        try:
            summary = target.trained(wait=True)
        except InputError as exc:
            self._refused(t, exc)
            return
        if summary is not None:
            self._trained(t, summary)

    def _trained(self, t: Try, summary: str) -> None:
        t.training_s = round(time.perf_counter() - self._t0, 4)
        self._try, self.state = t, "trying"
        self.say(f"{summary}; try it: K keep, X discard, R redo")

    def _refused(self, t: Try, exc: InputError) -> None:
        t.outcome = "too short" if "short" in str(exc) else "refused"
        target = self.target
        self._finish(t)
        part = getattr(target, "retake", lambda: "")() if target is not None else ""
        if part:     # a take in parts keeps the parts before (a sequential take's main)
            self._part, self.state = part, "ready"
            self.say(f"{exc}: R records {part} again, X cancels")
            return
        self.state = "idle"
        self.say(f"{exc}: R to record again")

    def _keep(self, target: Target, arg: str) -> None:
        if self.state != "trying":    # ready: the main is recorded, its reaction not yet
            self.say("still training: K once it plays" if self.state == "training"
                     else f"nothing to keep yet: R records {self._part}" if self.state == "ready"
                     else "nothing to keep yet: R stops the take, then K keeps it"
                     if self.state == "recording"
                     else "nothing to keep yet: the take starts when the countdown ends "
                          "(R cancels it)" if self.state == "countdown"
                     else "nothing to keep: R records a take")
            return
        name = target.keep()
        self.state = "idle"
        if self._try is not None:
            self._try.name = name
            self._finish(self._try, "kept")
        self.undo_stack.append(Undo(f"keep {name}", lambda: self._unkeep(target, name),
                                    target.name))
        self.say(f"kept as {name}{getattr(target, 'kept_in', '')}")   # where it was saved

    def _unkeep(self, target: Target, name: str) -> None:
        """The undo of a keep: ``name`` leaves the library, and the session log says so (a
        line of its own, outcome "keep undone"), so a review does not count the take kept."""
        target.remove(name)
        self._item_line(target, "keep undone", name)

    def _discard(self, target: Target, arg: str) -> None:
        if self.state in ("trying", "training"):
            self._drop("discarded")
            self.say("take discarded")
        elif self.state in ("countdown", "recording", "ready"):
            self._drop("")
            self.say("take cancelled")
        else:
            self.say("nothing to discard")

    def _redo(self, target: Target, arg: str) -> None:
        if self.state in ("trying", "training"):
            self._drop("redone")
        elif self.state in ("countdown", "recording", "ready"):
            self._drop("")
        if self.state == "idle":
            self.state, self.until = "countdown", self._t + self.countdown_s

    def _drop(self, outcome: str) -> None:
        """Back to what played before the take; the try is logged with ``outcome`` (a take
        cancelled before it was trained, outcome "", is not a try)."""
        target = self.target
        if target is not None:
            target.revert()
        if self._try is not None and outcome:
            self._finish(self._try, outcome)
        self._try, self._part, self.state = None, "", "idle"

    def _finish(self, t: Try, outcome: str | None = None) -> None:
        if outcome is not None:
            t.outcome = outcome
        self.tries.append(t)
        self._try = None
        if self.target is not None:
            self._log(t, self.target)

    def _log(self, t: Try, target: Target) -> None:
        if self.log_try is not None:
            try:
                self.log_try(t, target)
            except Exception:  # the session log must never stop the studio
                log.exception("studio: session log failed")

    def _only_target(self, target: Target, arg: str) -> None:
        self.say(f"Tab: {target.name} is the only designer target")   # not a broken key

    def _assign(self, target: Target, arg: str) -> None:
        fn = getattr(target, "assign", None)
        if fn is not None:
            self.say(fn())
        else:           # said, so that the key is not taken for broken
            self.say(f"A: a {target.what} has no motion to assign (MOP actions do)")

    def _window(self, target: Target, arg: str) -> None:
        """+/-: the focused character's follower window (MOP), while nothing is recorded."""
        fn = getattr(target, "step_window", None)
        if fn is None:
            self.say(f"+/-: a {target.what} has no follower window (MOP actions do)")
        elif self.state not in ("idle", "trying"):
            self.say("+/-: the window changes between takes, not while one is recorded")
        else:
            self.say(fn(-1 if arg == "-" else 1))

    def close(self) -> None:
        """The studio stops (Esc, the end of a run): the take is dropped, and one tried (or
        training) or still recorded (or a main part waiting for its reaction) is logged with
        outcome "quit", so the session log still shows it, and saved beside it
        (:meth:`SessionLog.save_take <tabletop.studio.session.SessionLog.save_take>`, not in
        the library: nothing loads it), named in the log and on the overlay. A take recorded
        too short to be of use is not: the log says why."""
        if self.state == "idle":
            return
        left, tried = self.selected, self.state in ("trying", "training")
        saved, why, react = "", "", ""
        if self._try is None:
            why = "" if tried else "nothing recorded yet (the countdown)"
        elif self.save_take is None:      # a replay's: the run it replays saved it
            why = "" if tried else "a replay saves no takes (the run it replays did)"
        else:
            saved, why = (self._save_made(self.target, "tried_take", "take tried"), "") \
                if tried else self._save_recorded(self.target)
            self._try.take = Path(saved).name if saved else ""
            # (the countdown before a take's next part: it waits between parts, "ready")
            self._try.take_state = "" if not saved else "ready" if self._part and \
                self.state == "countdown" else self.state
            if not tried and self.target is not None:
                self._try.duration_s = round(self.target.seconds(), 3)
            react = self._save_made(self.target, "recorded_reaction", "reaction recorded") \
                if saved and not tried else ""
            self._try.take_reaction = Path(react).name if react else ""
        self._drop("quit" if tried or saved else "")
        said = f"; saved as {saved} (not in the library)" if saved else ""
        said += f"; its reaction so far as {react}" if react else ""
        what = "tried, not kept," if tried else "recorded, not tried," if saved or (
            self.save_take is None and why.startswith("a replay")) else "cancelled"
        if tried or saved:     # on the overlay while a kiosk's applied config edit rebuilds
            self._show(f"{left}: take {what.rstrip(',')}{said}", MESSAGE_S)
        log.info("studio: %s: take %s at quit%s%s", left, what, said,
                 f"; nothing saved: {why}" if why else "")

    def _save_recorded(self, target: Target | None) -> tuple[str, str]:
        """The take ``target`` still records, saved by :attr:`save_take`: (its file, "") or
        ("", why none was saved)."""
        fn = getattr(target, "recorded_take", None)
        if fn is None:
            return "", "this target keeps no take recorded at quit"
        try:
            made = fn()
            if isinstance(made, str):
                return "", made
            return self.save_take(*made), ""      # "" when not written: said in the log
        except Exception:     # (a disk full): the quit goes on, the log says why none
            log.exception("studio: the take recorded was not saved")
            return "", "it could not be written"

    def _save_made(self, target: Target | None, made_by: str, what: str) -> str:
        """The take ``target``'s method ``made_by`` makes (``tried_take``: the take it tries;
        ``recorded_reaction``: a sequential take's reaction cut short at quit, its main part
        saved), saved by :attr:`save_take`: its file, or "" (none, or not written: said in the
        log, naming ``what``)."""
        fn = getattr(target, made_by, None)
        try:
            made = fn() if fn is not None else None
            return self.save_take(*made) if made is not None and self.save_take else ""
        except Exception:     # (a disk full): the quit goes on, the take's log line says none
            log.exception("studio: the %s was not saved", what)
            return ""

    # --- what the view draws ----------------------------------------------------------------------

    def poll(self) -> None:
        """Reload changed library files; a bad one is reported and skipped."""
        problems: list[str] = []
        for t in self.targets.values():
            problems.extend(t.poll())
            news = getattr(t, "news", None)   # a change made elsewhere (a delete), said once
            while news:
                self.say(news.pop(0))
        if problems != self.problems:
            for p in problems:
                if p not in self.problems:
                    log.error("library: %s (skipped; the others keep working)", p)
            for p in self.problems:     # the log's story closed, as the overlay's line goes
                if p not in problems:
                    log.info("library: no longer said (fixed or removed): %s", p)
            self.problems = problems

    def character(self, frame: Frame) -> CharacterState:
        """The studio's indicator (:func:`tabletop.studio.status.indicator`)."""
        return indicator(self, frame)

    def status(self) -> dict:
        return {"studio": {"state": self.state, "target": self.selected,
                           "tries": len(self.tries), "bad_files": list(self.problems)}}
