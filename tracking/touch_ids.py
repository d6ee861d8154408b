"""Touch ids unique within a frame when several origins number their touches on their own.

A TUIO sender numbers its cursors by session id and every sender starts counting at 0 or 1, a
serial device numbers its fingers from its own count, so two origins easily send the same id at
once: two fingers of one id on the bus are one finger to every engine, the recording and the
``tuio`` sink (which gave both the same session, so receivers kept only one of them).
:class:`TouchIds` gives each touch, keyed by its origin and its own id, the id it brought unless
another present touch already holds that id; then the smallest id that no present touch holds
or brings. An id stays with its touch for as long as the touch stays, so a finger never changes
id mid-drag because another finger came or went.
"""

from __future__ import annotations

from typing import Hashable, Sequence


class TouchIds:
    """Bus ids for touches keyed by (origin, own id); see the module docstring."""

    def __init__(self) -> None:
        self._ids: dict[Hashable, int] = {}

    def assign(self, keys: Sequence[Hashable], own: Sequence[int]) -> list[int]:
        """The bus id of each touch: ``keys`` (unique, one per present touch) in the same order
        as ``own`` (the id each brought). Touches absent from ``keys`` are forgotten."""
        given: dict[Hashable, int] = {}
        used: set[int] = set()
        for k in keys:   # a touch keeps the id it had
            i = self._ids.get(k)
            if i is not None and i not in used:
                given[k] = i
                used.add(i)
        brought = set(own)
        spare = 0
        for k, i in zip(keys, own):
            if k in given:
                continue
            if i in used:   # another touch holds it: the smallest id nobody holds or brings
                while spare in used or spare in brought:
                    spare += 1
                i = spare
            given[k] = i
            used.add(i)
        self._ids = given
        return [given[k] for k in keys]
