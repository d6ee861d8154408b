"""Humanoid pose tables shared within the process, by the content of the figure and the clip.

A rig's table (figure points at ``cache_hz`` steps of a clip's time, see
:meth:`behaviors.mop.puppetry.HumanoidRig.pose`) depends only on the skeleton, its projection,
whether the root travels, the sampling rate and the clip's keys. Every engine built from one
configuration loads the same clips into new rigs; keyed by that content, a rebuild reuses the
tables instead of working them out again (examples/mop.yaml: an engine build 52 -> 43 ms of
CPU).
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from typing import Callable

import numpy as np

from behaviors.motion.clips import Clip
from behaviors.motion.skeleton import ProjectedFigure

MAX_TABLES = 64   # tables kept (a DeepMimic clip's table: about 330 x 20 x 2 floats, 100 kB)
_tables: OrderedDict[bytes, np.ndarray] = OrderedDict()


def figure_key(figure: ProjectedFigure, travel: bool, hz: float) -> bytes:
    """A digest of everything a figure's points depend on, with the root's travel and rate."""
    h = hashlib.blake2b(digest_size=20)
    sk = figure.skeleton
    h.update(repr((sk.root_link, bool(travel), float(hz), figure.root_scale,
                   figure.rest_height, sorted(sk.tips))).encode())
    for j in sk.joints:
        h.update(repr((j.name, j.type, j.parent, j.child)).encode())
        for a in (j.xyz, j.rot, j.axis):
            h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    for k in sorted(sk.tips):
        h.update(np.ascontiguousarray(sk.tips[k], dtype=float).tobytes())
    h.update(np.ascontiguousarray(figure.projection.matrix, dtype=float).tobytes())
    h.update(np.ascontiguousarray(figure.projection.up, dtype=float).tobytes())
    return h.digest()


def clip_key(clip: Clip) -> bytes:
    """A digest of a clip's channels, keys and loop flag."""
    h = hashlib.blake2b(digest_size=20)
    h.update(repr((tuple((c.name, c.type) for c in clip.channels), clip.loop)).encode())
    h.update(np.ascontiguousarray(clip.times).tobytes())
    h.update(np.ascontiguousarray(clip.values).tobytes())
    return h.digest()


def shared_table(figure: bytes, clip: Clip, make: Callable[[], np.ndarray]) -> np.ndarray:
    """The table of ``clip`` on the figure digested as ``figure`` (:func:`figure_key`); made by
    ``make`` when no rig of this process made it yet. Read-only: rigs share it."""
    key = figure + clip_key(clip)
    table = _tables.get(key)
    if table is None:
        table = make()
        table.setflags(write=False)
        _tables[key] = table
        while len(_tables) > MAX_TABLES:
            _tables.popitem(last=False)
    else:
        _tables.move_to_end(key)
    return table
