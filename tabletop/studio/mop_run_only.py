"""A MOP studio target's takes kept for this run only (its engine has no ``library``): deleted
and given back by undo, and saved into a library a config edit gives the engine.
:class:`RunOnlyTakes` is a mixin of :class:`~tabletop.studio.mop_target.MopTarget` (its state
is the target's)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Callable

from tabletop.files import keep_under_free_name
from tabletop.frames import InputError

if TYPE_CHECKING:
    from behaviors.mop.stage import MopStage


class RunOnlyTakes:
    """The takes a character kept without a library (a mixin)."""

    stage: MopStage
    character: str
    kept: str | None
    run_only: list[str]        # kept without a library: lost at a rebuild
    _motions: dict[str, str]   # their motions as the config names them

    def _remove_unsaved(self, name: str) -> Callable[[], None]:
        """Without a library: the action kept for this run only leaves the character; the
        undo gives it back (same action, same samples)."""
        st = self.stage
        if name not in st.templates[self.character]:
            raise InputError(f"{self.character} has no action {name!r}")
        performer, samples = st.templates[self.character][name]
        action = st.puppets[self.character].actions[name]
        st.remove_action(self.character, name)
        run_only = name in self.run_only
        if run_only:
            self.run_only.remove(name)
        was_kept = self.kept == name
        if was_kept:
            self.kept = None

        def restore() -> None:
            st.put_action(self.character, action, performer, samples)
            if run_only and name not in self.run_only:
                self.run_only.append(name)
            if was_kept and self.kept is None:
                self.kept = name
        return restore

    def save_run_only(self, lib: Path) -> list[str]:
        """Save the takes kept for this run only into ``lib`` (a config edit gives the engine
        a library: the rebuild would drop them), each under the next free ``takeN`` when the
        library has its name (a take1 of an earlier session); one line each, saved or why not."""
        from tabletop.plugins.mop_library import save_to_library
        st, c, lines = self.stage, self.character, []
        for name in self.run_only:
            if name not in st.templates[c]:
                continue
            performer, samples = st.templates[c][name]
            # as the config names it ("grin.json"): the clip's own name ("grin") loads no file
            motion = self._motions.get(name) or st.puppets[c].actions[name].clip.name
            names = st.performers[performer].names
            under = [name]        # a library from an earlier session has its own take1...

            def rename(new: str) -> None:
                under[0] = new

            try:
                line = keep_under_free_name(
                    lambda: save_to_library(lib, c, under[0], samples, names, motion, st.rate_hz),
                    rename, lambda: self._free_in(lib))
                lines.append(line if under[0] == name else
                             f"{c}/{name} renamed {under[0]} ({name} is in the library "
                             f"already): {line}")
            except (InputError, OSError) as exc:
                lines.append(f"{c}/{name} (kept for this run only) not saved: {exc}")
        self.run_only, self._motions = [], {}
        return lines

    def _free_in(self, lib: Path) -> str:
        """The first ``takeN`` that is none of the names ``lib`` holds for the character, nor
        of its actions."""
        from behaviors.mop.take import free_take_number
        from tabletop.plugins.mop_library import library_names
        taken = library_names(lib, self.character) | set(self.stage.templates[self.character])
        return f"take{free_take_number(taken)}"
