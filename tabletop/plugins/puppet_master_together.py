"""The Puppet Master reactors of one installation stepped together, once per tick.

At the first Puppet Master engine's step of a tick every engine of the group reads its main,
and their reactors step together (:func:`behaviors.puppet_master.together.update_together`):
each plans against the others' poses of the previous tick, then the ends of their steps and
their shown poses are moved apart jointly, so no engine order decides who yields. Each engine
then returns its own result at its step. An engine that reads a character in the same tick
from an engine listed after the first Puppet Master engine cannot be read that early: it steps
alone at its own place, against the others' latest poses (so does one with ``keep_apart``
off, a designer's take and a reactor waiting for its main).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Protocol

from tabletop.frames import CharacterState, Frame
from tabletop.plugins.puppet_master_mains import bound_characters

if TYPE_CHECKING:
    from tabletop.registry import BuildContext

GROUP_KEY = "puppet_master.together"


class PuppetMasterEngine(Protocol):
    """What the group reads of a Puppet Master engine (tabletop.plugins.puppet_master)."""

    name: str
    reactor: Any
    board: Any
    size: float                 # body length, metres
    table: tuple[float, float, float, float]    # x0, y0, x1, y1, metres

    def prepare(self, frame: Frame) -> tuple[str, Any]: ...

    def reacting(self, x: float, y: float, d: float,
                 main: tuple[float, float, float]) -> CharacterState: ...


class Together:
    """The group of engines stepped together and this tick's results (by engine name)."""

    def __init__(self) -> None:
        self.members: dict[str, PuppetMasterEngine] = {}
        self.seq: int | None = None
        self.results: dict[str, tuple[CharacterState, ...] | Exception] = {}

    def join(self, engine: PuppetMasterEngine) -> None:
        """``engine`` steps with the group from the next tick (a rebuilt one replaces its
        namesake)."""
        self.members[engine.name] = engine

    def step(self, engine: PuppetMasterEngine, frame: Frame
             ) -> tuple[CharacterState, ...] | None:
        """``engine``'s characters of this tick, the whole group stepped at the first call
        of the tick; None for an engine outside the group."""
        if self.members.get(engine.name) is not engine:
            return None
        if frame.seq != self.seq:
            self.seq = frame.seq
            self.results = self._step_all(frame)
        out = self.results.pop(engine.name, None)
        if isinstance(out, Exception):
            raise out
        return out

    def _step_all(self, frame: Frame) -> dict[str, tuple[CharacterState, ...] | Exception]:
        from behaviors.puppet_master.together import update_together
        results: dict[str, Any] = {}
        group: list[tuple[PuppetMasterEngine, tuple[float, float, float]]] = []
        for e in self.members.values():
            try:
                kind, value = e.prepare(frame)
            except Exception as exc:          # reported at that engine's own step
                results[e.name] = exc
                continue
            if kind == "react":
                group.append((e, value))
            elif kind == "done":
                results[e.name] = value
        if not group:
            return results
        reactors = [e.reactor for e, _ in group]
        obstacles = [e.board.others(e.name, e.size) for e, _ in group]
        try:
            shown = update_together(reactors, frame.t, [p for _, p in group],
                                    [e.size for e, _ in group], group[0][0].table, obstacles)
        except Exception as exc:
            for e, _ in group:
                results[e.name] = exc
            return results
        for (e, pose), s in zip(group, shown):
            results[e.name] = (e.reacting(*s, pose),)
        return results


def group_of(options: dict, ctx: BuildContext, delayed: set[str],
             characters_of: Callable[[dict], list[str]]) -> Together | None:
    """The installation's group, where the Puppet Master engine ``options`` can step with it:
    it keeps apart, and every character it reads in the same tick (not in ``delayed``) is
    made by an engine listed before the first Puppet Master engine (``characters_of``: the
    names an engine entry makes)."""
    if not options["keep_apart"]:
        return None
    engines, _, mine = ctx.engines(options)
    first = next((i for i, e in enumerate(engines) if e.get("kind") == "puppet_master"), mine)
    made = [characters_of(e) for e in engines]
    for name in bound_characters(options["main"]):
        if name in delayed:
            continue
        k = next((i for i, chars in enumerate(made) if name in chars), len(engines))
        if k >= first:
            return None
    g = ctx.shared.get(GROUP_KEY)
    if g is None:
        g = ctx.shared[GROUP_KEY] = Together()
    return g
