"""A take kept under a free name: two runs may keep into one library at once, and a name chosen
when the take was trained can be saved by the other run first. The save refuses it
(:class:`NameTaken`); the take is renamed and saved again."""

from __future__ import annotations

from typing import Callable, TypeVar

from tabletop.errors import InputError

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
