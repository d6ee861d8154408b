"""The designer studio: record a take, train it, try it, keep or redo it, manage the library.

One state machine (:mod:`~tabletop.studio.machine`) drives every engine through a small
interface (:class:`~tabletop.studio.take.Target`); :mod:`~tabletop.studio.targets` adapts the
Puppet Master and MOP engines to it, :mod:`~tabletop.studio.pose_target` the touch-pose engine.
The ``studio:`` section of config.yaml is :data:`SCHEMA`.
"""

from __future__ import annotations

from typing import Any

from tabletop.schema import Bool, Context, FilePath, Number, Optional_, Record


def _check(studio: dict[str, Any], path: str, ctx: Context) -> None:
    """A session log folder that cannot be made is refused at load, not at the first try."""
    if studio["folder"] is not None:
        from tabletop.studio.session import unusable
        why = unusable(studio["folder"])
        if why:
            raise ctx.error(f"{path}.folder", f"cannot hold the session log: {why}")


SCHEMA = Record({
    "enabled": Bool(False, doc="studio mode (same as run --studio)"),
    "countdown_s": Number(3.0, lo=0.0, hi=30.0, doc="countdown before a take records, seconds"),
    "markers": Record({
        "record": Optional_(Number(integer=True, lo=0), default=45,
                            doc="marker that starts a take (lifting it stops the take)"),
        "stop": Optional_(Number(integer=True, lo=0), default=46, doc="marker that stops a take"),
        "keep": Optional_(Number(integer=True, lo=0), default=47, doc="marker that keeps the take"),
        "redo": Optional_(Number(integer=True, lo=0), default=48, doc="marker that redoes it"),
        "next": Optional_(Number(integer=True, lo=0), default=49,
                          doc="marker that selects the next engine target"),
    }, doc="control markers placed on the table (marker ids; null: none)"),
    "debounce_s": Number(0.3, lo=0.0, hi=5.0, doc="a marker must be seen (or gone) this long"),
    "folder": Optional_(FilePath(must_exist=False, kind="dir"),
                        doc="session logs and review sheets (default: studio/ beside the config)"),
    "review": Bool(True, doc="draw a review sheet (PNG) for every try"),
}, check=_check)
