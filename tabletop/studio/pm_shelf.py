"""The Puppet Master studio target's library shelf: the behaviours of its library folder to
pick from, rename and delete, the one in play reloaded when its files change, the library's bad
files reported. :class:`BehaviorShelf` is a mixin of
:class:`~tabletop.studio.targets.PuppetMasterTarget` (its state is the target's)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable

from tabletop import library
from tabletop.files import atomic_write_text
from tabletop.frames import InputError
from tabletop.kiosk.watch import Poller
from tabletop.studio.folders import not_config_named, rename_folder, trash
from tabletop.studio.reloader import load_and_train

LOAD_S = 0.15   # a picked library behaviour plays this long after the pick (frame time): an
                # 80 s demonstration trains in 44-67 ms, so the loop rarely waits


def _about(problem: str, folder: Path) -> bool:
    """``problem`` names ``folder`` or a file in it (one of ``lover-2`` is not ``lover``'s)."""
    f = str(folder)
    return problem.startswith((f + os.sep, f + ":"))


class BehaviorShelf:
    """Picking, renaming, deleting and reloading the library's behaviours (a mixin)."""

    started_problems: tuple[str, ...] = ()   # the studio logs the library's bad files itself
    _edited: Path | None = None   # the folder in play reloaded because its files changed

    def items(self) -> list[str]:
        return library.list_behaviors(self.lib)

    def current(self) -> str | None:
        if self.playing is not None and self.playing.parent == self.lib:
            return self.playing.name
        return None

    def shown(self) -> str | None:
        """The behaviour in play as the status line names it: also one from outside the library
        (the engine's own ``behavior``), named with "(not in the library)", and one deleted
        (or its keep undone) that plays on from memory, "pet (deleted)" as the engine names it."""
        if self.playing is not None and self.playing.parent != self.lib:
            return f"{self.playing.name} (not in the library)"
        if self.playing is None and self.engine.behavior is not None:
            return self.engine.behavior_name or None
        return self.current()

    def use(self, name: str) -> None:
        self._load(self.lib / name, known=True)

    def _load(self, folder: Path, known: bool = False) -> None:
        """Play ``folder``: read and trained in the loader (the behaviour in play goes on until
        :meth:`between_ticks`), or within the tick without background training. ``known``: a
        folder the library's listing found bad raises its InputError now (a pick passes over
        it); one found bad in the worker is said then, and the shelf names again what it
        named before the pick (a pick replacing one in flight: before the first)."""
        if self.loader is None:
            behavior, reactor, source = load_and_train(folder, self.engine.rate_hz,
                                                       self.engine.table)
            self.engine.play(behavior, source["name"], reactor)
        else:
            bad = next((p for p in self._problems if _about(p, folder)), None) if known else None
            if bad is not None:
                raise InputError(bad)
            if self._loading is None:
                self._before = (self.playing, self.play_poller, self.removed)
            self.loader.start(load_and_train, folder, self.engine.rate_hz, self.engine.table)
            self._loading, self._load_at = folder, self._now + LOAD_S
        self.playing, self.removed = folder, None
        self.play_poller = Poller(folder)

    def between_ticks(self, t: float) -> None:
        """Before the engines of the tick at frame time ``t`` (s): a behaviour trained in the
        loader plays from the first tick LOAD_S after it was picked, waiting for it there if
        it is not done (:meth:`flush`)."""
        self._now = t
        if self._loading is not None and t >= self._load_at:
            self.flush()

    def flush(self) -> None:
        """Wait for the loader's behaviour and swap it in now (a take begins, an item is
        renamed or deleted: they act on what plays). While a take is tried it becomes what a
        discard goes back to. One that does not load is said (a bad library file); the one in
        play goes on, and a failed pick leaves the shelf as it was."""
        if self._loading is None or self.loader is None:
            return
        self.loader.wait()
        done, folder, self._loading = self.loader.poll(), self._loading, None
        before, self._before = self._before, (None, None, None)
        reload = folder == before[0]
        if isinstance(done, Exception):
            if not reload:
                self.playing, self.play_poller, self.removed = before
            elif folder.parent == self.lib and not folder.exists():
                self._gone(folder)
                return
            self._problems = [p for p in self._problems
                              if not _about(p, folder) and p != str(done)] + [str(done)]
            e = self.engine
            self.news.append(
                f"{folder.name} not reloaded: {done}; the version read before plays on" if reload
                else f"{folder.name} not played: {done}; still playing "
                     f"{e.behavior_name if e.behavior is not None else 'nothing'}")
        elif done is not None:
            self._problems = [p for p in self._problems if not _about(p, folder)]
            if reload and self._edited == folder:   # said as its refusal is (an edit took:
                self.news.append(f"{folder.name} reloaded: its files changed")   # outside the
            self._edited = None                        # studio logged too; not a ] re-pick)
            behavior, reactor, source = done
            if self.pending is not None:
                self.previous = (behavior, source["name"])
            else:
                self.engine.play(behavior, source["name"], reactor)

    def rename(self, old: str, new: str, undo: bool = False) -> None:
        """Rename the folder and the name its behavior.yaml says; an undo gives the file back
        as it was (a folder made by hand as "my lover" said "lover"), unless it was edited
        since. A yaml that cannot be written puts the folder's old name back (the error said)."""
        self.flush()
        if not undo:
            not_config_named(self.lib / old, self.config_named)
        rename_folder(self.lib, old, new, check=not undo)
        path = self.lib / new / library.BEHAVIOR_FILE
        try:
            before = self._yaml_before.pop(old, None) if undo else None
            if before is not None and path.read_bytes() == before[1].encode("utf-8"):
                atomic_write_text(path, before[0])
            else:
                written = library.write_name(self.lib / new, new)
                if written is not None:
                    self._yaml_before[new] = written
        except OSError:
            rename_folder(self.lib, new, old, check=False)
            raise
        if self.current() == old:
            self.playing = self.lib / new
            self.engine.behavior_name = new
            self.play_poller = Poller(self.playing)

    def remove(self, name: str) -> Callable[[], None]:
        """Delete ``name`` into the trash. The item in play plays on from memory, no longer
        in the library (nothing to reload, delete or rename) until undo puts it back."""
        self.flush()
        folder, was_playing = self.lib / name, self.current() == name
        not_config_named(folder, self.config_named)
        put_back = trash(folder)
        if was_playing:
            self.playing, self.play_poller = None, None
            self.engine.behavior_name = f"{name} (deleted)"

        def restore() -> None:
            put_back()
            if was_playing and self.playing is None:
                self.playing, self.play_poller = folder, Poller(folder)
                self.engine.behavior_name = name
        return restore

    def poll(self) -> list[str]:
        """Reload the behaviour in play when its files change; report the library's bad
        files (each is skipped, the others keep working)."""
        problems = self._problems
        # not while a take trains or is tried: its change is seen after the take
        if (self.pending is None and self._training is None and self.playing is not None
                and self.play_poller is not None and self.play_poller.changed()):
            try:
                self._edited = self.playing
                self._load(self.playing)
                if self.loader is None:   # read now; in a worker, its problems stand until
                    # it has read (flush): dropped here, one still bad was said again after
                    # "no longer said (fixed or removed)"
                    problems = [p for p in problems if not _about(p, self.playing)]
            except InputError as exc:
                if self.playing.parent == self.lib and not self.playing.exists():
                    self._gone(self.playing)
                    problems = [p for p in problems if not _about(p, self.removed)]
                else:
                    problems = problems + [str(exc)]
        if self.lib_poller.changed():
            if self.removed is not None and self.removed.exists():
                self._back(self.removed)
            # the library is listed afresh; only a reload problem of a behaviour in play from
            # outside the library stays
            problems = self._library_problems(
                [p for p in problems if self.playing is not None
                 and self.playing.parent != self.lib and _about(p, self.playing)])
        self._problems = problems
        return problems

    def _named(self, name: str) -> None:
        """The engine's name of the behaviour in play (or, while a take is tried, of the one
        a discard goes back to)."""
        if self.pending is None:
            self.engine.behavior_name = name
        else:
            self.previous = (self.previous[0], name)

    def _gone(self, folder: Path) -> None:
        """The behaviour in play was deleted (or renamed) elsewhere, another studio on this
        library: it plays on from memory, as after a delete here (not reported as a bad
        library file, "behaviour folder not found")."""
        self.playing, self.play_poller, self.removed = None, None, folder
        self._named(f"{folder.name} (deleted)")
        self.news.append(f"{folder.name} was removed from the library elsewhere; it plays on "
                         "from memory, ] plays another")

    def _back(self, folder: Path) -> None:
        """The deleted behaviour in play is back (undone elsewhere): it is in play again,
        reloaded at the next look (its files may be another's)."""
        self.playing, self.removed = folder, None
        self.play_poller = Poller(folder, since_start=True)
        self._named(folder.name)
        self.news.append(f"{folder.name} is back in the library")

    def _library_problems(self, kept: list[str]) -> list[str]:
        """``kept`` and the error of every behaviour in the library that does not load."""
        problems = list(kept)
        try:
            names = self.items()
        except InputError as exc:       # the library cannot be listed: said, the rest plays
            return problems + [str(exc)]
        for n in names:
            try:
                library.load_behavior(self.lib / n)
            except InputError as exc:
                problems.append(str(exc))
        return problems
