"""Touch ids unique within a frame when several origins number their touches on their own.

A TUIO sender numbers its cursors by session id and every sender starts counting at 0 or 1, a
serial device numbers its fingers from its own count, so two origins easily send the same id at
once: two fingers of one id on the bus are one finger to every engine, the recording and the
``tuio`` sink (which would give both one session, so receivers would keep only one of them).
:class:`TouchIds` gives each touch, keyed by its origin and its own id, the id it brought unless
another present touch already holds that id; then the smallest id that no present touch holds
or brings and that no other touch gave up in the last :data:`QUARANTINE_FRAMES` frames. An id
stays with its touch for as long as the touch stays, so a finger never changes id mid-drag
because another finger came or went.

A lifted touch's id is kept out of use for :data:`QUARANTINE_FRAMES` frames (0.5 s at 60 Hz)
for every *other* key, even one that brings that id: otherwise, with two senders counting from
0, a spare id given to one sender's finger would go to the other sender's next finger in the
very next frame, and touch-pose (which keys fingers by id) would drag the held part 0.5 m in one
tick.
The key that held the id may take it back at once, so a single origin with unique ids always
keeps the ids it brought (a sender reusing its own id for a new finger keeps it too): a rising
spare counter in a range senders do not use would keep this too, but gives every spare a large
id (1<<24 and up) in the recording and the ``tuio`` sink, and does not keep a brought id from
passing between origins, which the quarantine does.
"""

from __future__ import annotations

from typing import Hashable, Sequence

QUARANTINE_FRAMES = 30
"""Frames (calls of :meth:`TouchIds.assign`) a lifted touch's id stays out of use for others."""


class TouchIds:
    """Bus ids for touches keyed by (origin, own id); see the module docstring."""

    def __init__(self) -> None:
        self._ids: dict[tuple[Hashable, int], int] = {}
        self._lifted: dict[int, tuple[tuple[Hashable, int], int]] = {}   # id -> (key, frames left)

    def assign(self, touches: Sequence[tuple[Hashable, int]]) -> list[int]:
        """The bus id of each touch: ``touches`` holds one (origin, own id) pair per present
        touch, each unique; the pair is the touch's key. Touches absent are forgotten."""
        given: dict[tuple[Hashable, int], int] = {}
        used: set[int] = set()
        for k in touches:   # a touch keeps the id it had
            i = self._ids.get(k)
            if i is not None and i not in used:
                given[k] = i
                used.add(i)
        lifted = {i: (k, n - 1) for i, (k, n) in self._lifted.items() if n > 1}
        for k, i in self._ids.items():
            if k not in given:
                lifted[i] = (k, QUARANTINE_FRAMES)
        brought = {i for _origin, i in touches}
        spare = 0
        for k in touches:
            i = k[1]
            if k in given:
                continue
            if i in used or lifted.get(i, (k,))[0] != k:   # held, or lately another's: a spare
                while spare in used or spare in brought or spare in lifted:
                    spare += 1
                i = spare
            given[k] = i
            used.add(i)
            lifted.pop(i, None)
        self._ids = given
        self._lifted = lifted
        return [given[k] for k in touches]
