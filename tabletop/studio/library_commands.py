"""The studio's commands on the library item in play: switch (``designer.item_next`` /
``item_previous``), rename, delete and undo (see :mod:`tabletop.studio.machine`). None of them
acts while a take is under way or tried: they act on the item in play, not on the take."""

from __future__ import annotations

import time
from typing import Callable, NamedTuple

from tabletop.frames import InputError
from tabletop.studio.take import Target, Try


class Undo(NamedTuple):
    """One entry of the undo list: what it undoes ("keep pet"), the function undoing it, and
    the target it was done on (named when U is pressed with another one selected)."""

    what: str
    do: Callable[[], None]
    target: str


class LibraryCommands:
    """The library half of :class:`tabletop.studio.machine.Studio`: the commands that act on
    the library item in play, and the undo of a keep, rename or delete."""

    state: str
    quiet: bool
    undo_stack: list[Undo]

    @property
    def target(self) -> Target | None:
        raise NotImplementedError

    def say(self, text: str) -> None:
        raise NotImplementedError

    def _log(self, t: Try, target: Target) -> None:
        raise NotImplementedError

    def _busy(self, doing: str) -> bool:
        """Is a take under way? Then ``doing`` is refused, said: it acts on the library item
        in play, not on the take (a switch would train the take with another character's
        parameters; F2 on a take tried would rename the item played before it)."""
        why = self._busy_why(doing)
        if why:
            self.say(why)
        return self.state != "idle"

    def _busy_why(self, doing: str) -> str:
        if self.state in ("countdown", "recording", "ready"):
            return f"no {doing} during a take: finish it, or X cancels it"
        if self.state in ("trying", "training"):
            return f"no {doing} while a take is tried: K keeps or X discards it first"
        return ""

    def _item(self, target: Target, step: int) -> None:
        if self._busy("switching"):
            return
        items = target.items()
        if not items:   # (a character's configured actions are no library items: named here)
            where = getattr(target, "kept_in", "")
            self.say(f"nothing kept{where if where.startswith(' in ') else ''} yet: ] and [ "
                     "play what K keeps")
            return
        cur = target.current()
        # (from an item outside the library, the config's: ] plays the first, [ the last)
        i = (items.index(cur) + step if cur in items else min(step, 0)) % len(items)
        skipped: list[str] = []     # an item that does not load is passed over, named: ]
        for _ in items:             # on a broken first item played nothing, again and again
            try:
                target.use(items[i])
                break
            except InputError as exc:
                skipped.append(str(exc))
                i = (i + step) % len(items)
        else:
            raise InputError(f"no item of the library loads: {skipped[0]}")
        note = f"; skipped {len(skipped)} that do not load: {skipped[0]}" if skipped else ""
        self.say(f"playing {items[i]} ({i + 1} of {len(items)}){note}")

    def _item_next(self, target: Target, arg: str) -> None:
        self._item(target, 1)

    def _item_previous(self, target: Target, arg: str) -> None:
        self._item(target, -1)

    def may_rename(self) -> str:
        """F2 in the view: the name of the item the prompt renames, or "" when it may not open;
        then why is said at once (the same refusal as the rename's), not after a name was
        typed."""
        self.quiet = False
        target = self.target
        why = ("no designer target" if target is None else self._busy_why("renaming")
               or ("nothing to rename" if target.current() is None else ""))
        if why:
            self.say(why)
            return ""
        return str(target.current())

    def _rename(self, target: Target, arg: str) -> None:
        """``arg`` NEW renames the item in play; OLD=NEW (F2's prompt, OLD the item it named)
        only while OLD is in play (a name holds no '=': the last one splits)."""
        if self._busy("renaming"):
            return
        getattr(target, "flush", lambda: None)()    # a pick still loading plays (or fails)
        old = target.current()
        named, _, arg = arg.rpartition("=")
        if named and old is not None and named != old:
            self.say(f"nothing renamed: {old} plays now, not {named} (F2 renames {old})")
            return
        if old is None or not arg.strip():   # (a blank name: a kept action skipped at reload)
            self.say("nothing to rename" if old is None else "rename needs a new name")
            return
        if arg == old:     # Enter on the name it has: "cannot: lib/lover: already exists"
            self.say(f"nothing renamed: {old} is already its name")
            return
        self._renamed(target, old, arg)
        self.undo_stack.append(Undo(f"rename {old} -> {arg}",
                                    lambda: self._renamed(target, arg, old, undo=True),
                                    target.name))
        self.say(f"renamed {old} to {arg}")

    def _renamed(self, target: Target, old: str, new: str, undo: bool = False) -> None:
        """``old`` renamed ``new`` (``undo``: back), logged: the session log's kept take goes by
        the name its folder has."""
        target.rename(old, new, undo=undo)
        self._log(Try(target.name, target.what, time.time(), outcome="renamed", name=new,
                      renamed_from=old), target)

    def _delete(self, target: Target, arg: str) -> None:
        if self._busy("deleting"):
            return
        getattr(target, "flush", lambda: None)()
        name = target.current()
        if name is None:
            self.say("nothing to delete")
            return
        restore = target.remove(name)
        self._item_line(target, "deleted", name)
        self.undo_stack.append(Undo(f"delete {name}", lambda: self._restored(target, name, restore),
                                    target.name))
        self.say(f"deleted {name} (U undoes)")

    def _restored(self, target: Target, name: str, restore: Callable[[], None]) -> None:
        """The undo of a delete: ``name`` back in the library, logged ("restored")."""
        restore()
        self._item_line(target, "restored", name)

    def _item_line(self, target: Target, outcome: str, name: str) -> None:
        """A session log line of its own (no try) saying the item ``name`` changed: ``outcome``
        one of :data:`tabletop.studio.take.ITEM_LINES`; the review gives its kept take the
        outcome, so a take deleted (or its keep undone) is not counted kept."""
        self._log(Try(target.name, target.what, time.time(), outcome=outcome, name=name), target)

    def _undo(self, target: Target, arg: str) -> None:
        if self._busy("undoing"):
            return
        if not self.undo_stack:
            self.say("nothing to undo")
            return
        what, do, owner = self.undo_stack[-1]
        do()                  # one that cannot be done now (a read-only disk) stays to undo
        self.undo_stack.pop()
        # the list is the studio's, not the selected target's: another target's undo names it
        self.say(f"undone: {what}" + ("" if owner == target.name else f" of {owner}"))
