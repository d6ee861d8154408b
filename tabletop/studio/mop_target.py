"""One character of a MOP engine as a studio target (an action slot).

The take is the character's performer; training is the stage's (a new action, followed at once,
its followers built in the stage's worker); kept takes are the engine's action library
(:func:`tabletop.plugins.mop_library.save_to_library`), reloaded when its files change: new and
fixed actions are followed at once, removed ones dropped, a bad file reported and skipped.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING, Callable, ContextManager

import numpy as np

from behaviors.mop.takes import MIN_TAKE_SAMPLES
from tabletop.frames import Frame, InputError
from tabletop.kiosk.watch import Poller, tree_signature
from tabletop.studio.folders import named_folder, trash
from tabletop.studio.mop_likeness import too_like
from tabletop.studio.mop_run_only import RunOnlyTakes
from tabletop.studio.pm_take import Unseen
from behaviors.worker import Worker, close_workers

if TYPE_CHECKING:
    from behaviors.mop.stage import MopStage


log = logging.getLogger(__name__)

#: States the studio's +/- keys step a character's window by.
WINDOW_STEP = 5


class MopTarget(RunOnlyTakes):
    """One character of a MOP engine (``ENGINE/CHARACTER``) as a studio target: its takes are
    recorded, trained and kept by the stage's take API (:class:`behaviors.mop.stage.MopStage`,
    from :class:`behaviors.mop.takes.DesignerTakes`)."""

    what = "action"

    def __init__(self, stage: MopStage, character: str, lib: Path | None,
                 background: bool = True) -> None:
        self.stage, self.character, self.lib = stage, character, lib
        self.base: Path | None = None        # the config's folder (the keep's line)
        if background and stage.worker is None:   # the stage's followers built off the hot path
            stage.worker = Worker(f"{stage.name}-training")
        self._summary = ""
        self._likeness: Worker | None = None   # the take's replay, off the hot path
        self._like: str | None = None          # what the take is too like ("" nothing) once known
        self.name = f"{stage.name}/{character}"
        self.kept: str | None = None
        self.run_only: list[str] = []     # kept without a library: lost at a rebuild
        self._motions: dict[str, str] = {}  # their motions as the config names them
        self.demo: np.ndarray | None = None
        self.unseen = Unseen()       # how long the performer's inputs were missing from the take
        self._poller = (Poller(lib / character,
                               read=getattr(stage, "library_read", {}).get(character))
                        if lib is not None else None)
        self._problems: list[str] = list(getattr(stage, "library_problems", {}).get(character, []))
        self.started_problems = tuple(self._problems)   # logged by the stage's start
        self.loaded = set(getattr(stage, "library_loaded", {}).get(character, []))

    def close(self, deadline: float | None = None) -> bool:
        """The studio closes: the stage's training worker's thread ends, waited for until
        ``deadline`` (each character of the stage closes it; a closed worker closes again at
        once); says whether it did."""
        return close_workers(self.stage.worker, self._likeness, deadline=deadline)

    @property
    def cue(self) -> str:
        """The countdown's line: the performer the take records and its inputs, so the
        designer knows which puck (or finger, or stream) performs."""
        p = self.stage.performers[self.stage.performer_of(self.character)]
        what = ", ".join(i.shown for i in p.inputs)     # "puck 1", "finger", "stream arm"
        return f"get ready: {p.name} ({what}) performs {self.character}'s new action"

    def begin(self, frame: Frame) -> None:
        self.unseen, self.demo = Unseen(), None
        self.stage.begin_take(self.character, frame)

    def resume(self, frame: Frame) -> None:
        pass                                  # an action is one part

    def record(self, frame: Frame) -> str:
        """The stage samples the performer in its step (a frame without one of its inputs, a
        puck, a finger or a stream, gives no sample); this says which of them the frame lacks
        ("recording: no puck 1, finger"), and tallies how long."""
        p = self.stage.performers[self.stage.performer_of(self.character)]
        missing = [i.shown for i in p.inputs if i.absent(frame)]
        self.unseen.tally(frame.t, missing)
        return f"recording: no {', '.join(missing)}" if missing else ""

    def ended(self) -> bool:
        return False

    def cut(self) -> str:
        return ""

    def trained(self, wait: bool) -> str | None:
        """Between ticks: the summary once the stage's new followers are installed."""
        self.stage.install_built(wait)
        if self.stage.building:
            return None
        if self.stage.build_error:
            raise InputError(self.stage.build_error)
        if self._like is None and self._likeness is not None:
            if wait:
                self._likeness.wait()
            done = self._likeness.poll()
            if done is None:
                return None
            self._like = done if isinstance(done, str) else ""   # a failed replay says nothing
        return self._summary + self._too_like_note()

    def seconds(self) -> float:
        take = self.stage.take
        return len(take.rows) / self.stage.rate_hz if take is not None else 0.0

    def train(self) -> str | None:
        try:
            self._summary = self.stage.stop_take()
        except InputError as exc:     # a puck never seen made it short, not the designer
            lost = self.unseen.words()
            raise InputError(f"{exc}; {lost}" if lost else str(exc)) from None
        self._summary += self.unseen.note()
        self.demo = np.array(self.stage.take.samples(), dtype=float)
        self._measure_likeness()
        return None if self.stage.building or self._like is None else \
            self._summary + self._too_like_note()

    def _measure_likeness(self) -> None:
        """Replay the take through a follower of its performer's actions
        (:mod:`tabletop.studio.mop_likeness`) in a worker of its own, whether or not the stage
        builds its followers in one: the replay takes 30-65 ms, on top of a stop's tick that
        trains within it (bench/studio.py's MOP round without a training worker, the stop's
        tick's CPU time, median of 5: 81.8 ms with the replay in it, 11.7 ms without).
        :attr:`_like` is None until it is known (the studio's ``trained`` waits for it at its
        frame-time swap, so the tick the note is said on depends on the frames alone)."""
        st, take = self.stage, self.stage.take
        self._like = ""                 # the take is tried all the same, without the check
        try:
            templates, routes, args = st.follower_plan(take.performer)
        except Exception:
            log.exception("%s: the take's likeness could not be planned", self.name)
            return
        key = next((k for c, a, k in routes if (c, a) == (take.character, st.take_action)),
                   None)
        if key is None:                 # the take is not among its performer's routes yet
            return
        names = {k: (c, a) for c, a, k in reversed(routes) if (c, a) != (take.character,
                                                                        st.take_action)}
        self._like = None
        if key in names:                # recorded exactly as another: the same template
            self._like = self._named(names[key])
            return

        def measure() -> str:
            like = too_like(st.make_follower, templates, key, **args)
            return self._named(names[like]) if like in names else ""
        if self._likeness is None:
            self._likeness = Worker(f"{st.name}-likeness")
        self._likeness.start(measure)

    def _named(self, route: tuple[str, str]) -> str:
        """An action as the designer knows it: its name, with its character when another's."""
        c, a = route
        return a if c == self.character else f"{c}'s {a}"

    def _too_like_note(self) -> str:
        """What the status line adds when the follower cannot tell the take from an action."""
        if not self._like:
            return ""
        return (f"; {self.stage.take_action} is too like {self._like}: MOP cannot tell them "
                "apart (K keeps it anyway)")

    def tried_take(self) -> tuple[str, str] | None:
        """The take being tried as its keep saves its template: (".csv", ``t`` and the
        performer's feature columns at the engine's rate); None without one."""
        take = self.stage.take
        if take is None or take.character != self.character or take.recording:
            return None
        return self._template_csv()

    def recorded_take(self) -> tuple[str, str] | str:
        """The take still recorded at quit, as :meth:`tried_take` gives one (its still ends
        kept), or why none: fewer samples than a take is learned from."""
        take = self.stage.take
        n = len(take.rows) if take is not None and take.character == self.character else 0
        if n < MIN_TAKE_SAMPLES:
            return f"take too short ({n} of {MIN_TAKE_SAMPLES} samples)"
        return self._template_csv()

    def _template_csv(self) -> tuple[str, str]:
        """The stage's take as its keep saves the template: t and the performer's features."""
        from tabletop.files import format_csv
        from tabletop.plugins.mop_library import template_table
        take = self.stage.take
        samples = np.asarray(take.samples(), dtype=float)
        names = self.stage.performers[take.performer].names
        return ".csv", format_csv(*template_table(samples, names, self.stage.rate_hz))

    def take_array(self) -> np.ndarray:
        take = self.stage.take
        return np.asarray(take.samples()) if take is not None else np.zeros((0, 0))

    def _take_named(self, name: str) -> bool:
        """Is ``name`` this character's pending take's?"""
        take = self.stage.take
        return take is not None and take.character == self.character \
            and self.stage.take_action == name

    def revert(self) -> None:
        if self.stage.take is not None and self.stage.take.character == self.character:
            named = self.stage.take_action
            self.stage.drop_take()
            if named in self.loaded:    # another run kept an action of its name: it plays
                self._applied()

    def assign(self) -> str:
        """A: the next motion, said with what plays it (its name alone does not say): the take
        being tried ("take1 -> curl", with what to do next, as after its stop) or the next
        take."""
        motion = self.stage.assign_motion(self.character)
        action = self.stage.take_action
        # (without it, A on a character of one motion, the example's bird, says its line again)
        only = (f" ({motion} is the only motion {self.character} has)"
                if len(self.stage.motions.get(self.character, ())) == 1 else "")
        if action is not None:
            return f"{action} -> {motion}{only}; try it: K keep, X discard, R redo"
        return f"the next take plays {motion}{only or ' (A: another motion)'}"

    def keep(self) -> str:
        """Keep the take under its name, or the next free one when another run on the library
        kept one of its name meanwhile (that one is then followed too, from this tick)."""
        named = self.stage.take_action
        stale = self._poller is not None and \
            tree_signature(self._poller.path) != self._poller.signature
        take = self.stage.take
        motion = self.stage.motion_of(take.character, take.motion_index) if take else ""
        action = self.stage.keep_take()
        self.kept = action
        if action != named or stale:    # the library changed since the watcher looked: all
            self._applied()             # of it is followed, not only this keep
        elif action and self._poller is not None:     # in play already: no reload for it
            self.loaded.add(action)
            self._poller.signature = tree_signature(self._poller.path)
        if action and self.lib is None:
            self.run_only.append(action)
            self._motions[action] = motion
        return action or ""

    @property
    def kept_in(self) -> str:
        """What the keep's line adds: the character's folder in the library, or, when nothing
        is saved, that an engine without a ``library`` keeps its takes for this run only, gone
        at the next start."""
        if self.lib is not None:
            return f" in {named_folder(self.lib / self.character, self.base)}"
        return (f" for this run only: engine {self.stage.name!r} has no library to save it in "
                "(give it library: FOLDER in the config)")

    def _entries(self) -> list[dict]:
        from tabletop.plugins.mop_library import read_library
        return read_library(self.lib, self.character) if self.lib is not None else []

    def items(self) -> list[str]:
        try:
            return sorted(a["name"] for a in self._entries())
        except InputError:
            return []

    def current(self) -> str | None:
        return self.kept

    def shown(self) -> str | None:
        """The kept action selected, as the idle line names it; with none, the actions the
        character knows (its config's), which it plays with no take kept; then the window its
        follower runs with, and the characters sharing it (+/- step it)."""
        others = self.stage.sharing(self.character)
        window = f", window {self.window}" + (f" shared with {', '.join(others)}" if others else "")
        window += " (+/-)"
        if self.kept is not None:
            return self.kept + window
        known = sorted(self.stage.templates.get(self.character, {}))
        return f"(none selected; it knows {', '.join(known)}){window}" if known else None

    @property
    def window(self) -> int:
        """The window (p, states either side of the progress) the character's performer's
        follower runs with (the largest its characters set)."""
        return self.stage.window(self.character)

    def step_window(self, sign: int) -> str:
        """+/-: the character's window, stepped by :data:`WINDOW_STEP` states from the one its
        follower runs with, within the schema's range (the paper's Evaluation: the user "might
        need to adjust the window size"); the followers whose window changes are rebuilt at
        once, and the character's window saved in its actions.yaml (atomically), read at the
        next start. The message gives the window the follower runs with: shared with other
        characters, it is the largest they set."""
        from tabletop.plugins.mop_library import WINDOW_RANGE
        lo, hi = WINDOW_RANGE
        old = self.window
        new = min(hi, max(lo, old + sign * WINDOW_STEP))
        own = self.stage.windows.get(self.character)
        if self.lib is not None and new != own:
            from tabletop.plugins.mop_library import write_library
            with self._locked():
                write_library(self.lib, self.character, self._entries(), window=new)
            if self._poller is not None:
                self._poller.signature = tree_signature(self._poller.path)
        if new != own:
            self.stage.set_window(self.character, new)
        where = (f"saved in {named_folder(self.lib / self.character, self.base)}"
                 if self.lib is not None else "for this run only (no library)")
        edge = " (its limit)" if new == old else ""
        now, others = self.window, self.stage.sharing(self.character)
        shared = "" if not others else f", shared with {', '.join(others)}" + (
            "" if now == new else " (the largest of its characters' with actions is used; "
                                  f"{self.character}'s is {new})")
        return f"{self.character}: window {now} states{edge}{shared}, {where}"

    def use(self, name: str) -> None:
        self.kept = name     # every kept action of a character plays; this one is selected

    def _write(self, entries: list[dict]) -> None:
        from tabletop.plugins.mop_library import write_library
        assert self.lib is not None
        write_library(self.lib, self.character, entries)

    def _locked(self) -> ContextManager[None]:
        """The library's lock, held while its entries are read, changed and written (another
        run may be keeping into it). InputError without a library."""
        from tabletop.plugins.mop_library import library_lock
        if self.lib is None:
            raise InputError(f"engine {self.stage.name!r} has no library: its takes are kept "
                             "for this run only, under the names they were kept as")
        return library_lock(self.lib, self.character)

    def rename(self, old: str, new: str, undo: bool = False) -> None:
        """Rename a kept action; a name the character already has (kept, configured or the take
        being tried) is refused: the reload would replace that action with this one, and undo
        would then remove it from the character (``undo`` changes nothing: names are entries)."""
        with self._locked():
            entries = self._entries()
            own = set(self.stage.templates[self.character]) - self.loaded   # not the library's
            if any(a["name"] == new for a in entries) or new in own:
                raise InputError(f"an action {new!r} already exists")
            self._write([dict(a, name=new) if a["name"] == old else a for a in entries])
        if self.kept == old:
            self.kept = new
        self._applied()

    def remove(self, name: str) -> Callable[[], None]:
        """Delete ``name``: its entry, and its template CSV into the library's ``.trash`` when
        it is the library's own and no other entry uses it (it stayed in place, and the next
        run's take of its name wrote over it). Returns the undo."""
        if self.lib is None:
            return self._remove_unsaved(name)
        folder = self.lib / self.character
        with self._locked():
            entries = self._entries()
            gone = [a for a in entries if a["name"] == name]
            others = {a["template"] for a in entries if a["name"] != name}
            files = {folder / a["template"] for a in gone if a["template"] not in others}
            backs = [trash(f) for f in files if f.parent == folder and f.is_file()]
            self._write([a for a in entries if a["name"] != name])
        was_kept = self.kept == name
        if was_kept:
            self.kept = None
        self._applied()

        def restore() -> None:
            # resumable: an undo that failed half-way (a read-only disk) is done again from
            # where it stopped, not refused for the template it already put back
            with self._locked():
                for back in backs:
                    back()
                entries = self._entries()
                self._write(entries + [a for a in gone if a not in entries])
            if was_kept and self.kept is None:
                self.kept = name               # in play again: F2 said "nothing to rename"
            self._applied()
        return restore

    def _applied(self) -> None:
        """The library as this target just changed it (delete, undo, rename) is followed from
        this tick on, and is no change for the watcher. Left to the watcher's next look (once a
        second of wall-clock time), the characters changed on another tick in a replay: the
        MOP studio session replayed with 371 of 1147 frames unlike the live run's."""
        self._reload()
        if self._poller is not None:
            self._poller.signature = tree_signature(self._poller.path)

    def poll(self) -> list[str]:
        """Reload the character's kept actions when its library files change: new and fixed
        ones are followed at once, removed ones dropped; a bad one is reported and skipped."""
        if self._poller is None or not self._poller.changed():
            return self._problems
        return self._reload()

    def _reload(self) -> list[str]:
        st = self.stage
        kept, self._problems = st.library_actions(self.character)
        names = {a.name for a, _ in kept}
        for gone in self.loaded - names:
            if gone != st.take_action:
                st.remove_action(self.character, gone)
        for action, samples in kept:
            if self._take_named(action.name):
                continue    # another run's keep of the take's name: the take is tried on
            st.put_action(self.character, action, st.performer_of(self.character), samples)
        self.loaded = names
        if self.kept is not None and self.kept not in names:
            self.kept = None
        return self._problems
