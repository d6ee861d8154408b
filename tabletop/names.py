"""Keeping a take under a free name when another run on the library took its name meanwhile.

Two runs (or two studios) may keep into one library at once: a name chosen when the take was
trained can be saved by the other run before this one saves. The save then refuses it
(:class:`NameTaken`), the take is renamed to the next free name and saved again.
"""

from __future__ import annotations

from typing import Callable, TypeVar

from tabletop.frames import InputError

T = TypeVar("T")

NAME_TRIES = 100     # refusals before a keep gives up (each one a name another run just took)


class NameTaken(InputError):
    """A save refused the name: the library holds one of that name already."""


def keep_under_free_name(save: Callable[[], T], rename: Callable[[str], None],
                         free_name: Callable[[], str], tries: int = NAME_TRIES) -> T:
    """``save()``; on :class:`NameTaken`, ``rename(free_name())`` and save again. InputError
    (nothing saved, the take stays) after ``tries`` refusals, never a keep said done that
    saved nothing."""
    for _ in range(tries):
        try:
            return save()
        except NameTaken:
            rename(free_name())
    raise InputError(f"not saved: its name was taken {tries} times in a row; keep it again")
