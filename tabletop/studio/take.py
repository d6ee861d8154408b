"""What the studio machine (:mod:`tabletop.studio.machine`) works with: the :class:`Target`
an engine offers it, and the :class:`Try` the session log records of each take."""

from __future__ import annotations

import dataclasses
from typing import Callable, Protocol

from tabletop.frames import Frame


class Target(Protocol):
    """What the studio needs of an engine: one designer target (a behaviour, an action slot)."""

    name: str   # the focus name (Frame.focus)
    what: str   # "behaviour", "action", ...
    kept_in: str  # what the keep's line adds: where kept takes are saved (" in lib/")
    started_problems: tuple[str, ...]   # bad library files its engine logged as it started

    def begin(self, frame: Frame) -> None: ...            # a take starts now
    def resume(self, frame: Frame) -> None: ...           # its next part (cut() named) starts
    def record(self, frame: Frame) -> str: ...            # sample this tick; a problem or ""
    def ended(self) -> bool: ...                          # the part ended by itself
    def cut(self) -> str: ...                             # part stopped: "" done, else the next
    def seconds(self) -> float: ...                       # length of the part so far
    def train(self) -> str | None: ...                    # train, play it; None: training in
                                                          # the background; raises InputError
    def trained(self, wait: bool) -> str | None: ...      # between ticks: it plays (wait: once
                                                          # trained), else None; InputError
    def revert(self) -> None: ...                         # back to what played before the take
    def keep(self) -> str: ...                            # save the take; returns its name
    # optional: tried_take() -> (suffix, text) | None, the take tried as its keep saves it
    def items(self) -> list[str]: ...                     # the library's items, sorted
    def current(self) -> str | None: ...                  # the item in play
    def use(self, name: str) -> None: ...                 # play a library item
    def rename(self, old: str, new: str, undo: bool = False) -> None: ...  # undo: back
    def remove(self, name: str) -> Callable[[], None]: ...  # returns its restore
    def poll(self) -> list[str]: ...                      # reload changed files; problems


ITEM_LINES = ("renamed", "keep undone", "deleted", "restored")
"""The session log's outcomes of a library item changed after its take (a line of its own, no
try): F2 or its undo, U after K, Delete, U after Delete."""


@dataclasses.dataclass
class Try:
    """One take as the session log records it."""

    target: str
    what: str
    started: float
    duration_s: float = 0.0
    samples: int = 0
    training_s: float = 0.0    # from the stop until the take plays (a worker's wait included)
    outcome: str = ""          # a take: kept | discarded | redone | too short | refused | quit;
                               # a library line (ITEM_LINES): renamed | keep undone | deleted
                               # | restored
    name: str = ""
    review: str = ""
    renamed_from: str = ""     # outcome "renamed": the item's name before (F2, or its undo)
    take: str = ""             # outcome "quit": the file the take tried was saved in, or ""
    take_state: str = ""       # outcome "quit" with a take: the studio's state it was saved in
                               # (trying | training | recording | ready)
    take_reaction: str = ""    # and a sequential take's reaction cut short: its file
