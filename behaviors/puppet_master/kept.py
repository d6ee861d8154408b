"""Behaviours trained from behaviour folders, kept for the process.

An applied config edit rebuilds the installation and trains every Puppet Master character
again from its folder (40-60 ms each for the shipped 60-80 s demonstrations, ~400 ms for
600 s), within the rebuild's pause. :func:`train` (the engine's build) gives the behaviour
trained before from the same demonstration (its float64 bytes, so a changed file trains
afresh) and the same parameters; a Behavior is shared read-only by any number of reactors
(behavior.py). Takes (trained from memory, not from a folder) are not kept: a studio trying a
take every few minutes would fill it. Nor are hot reloads (studio.reloader): a folder whose
files changed on disk is trained afresh, whatever it holds, a new behaviour object.

The kept behaviours are bounded by their training samples (KEPT_SAMPLES, least recently
used dropped first): a behaviour holds ~1.4 kB a sample (the afraid character's
3,200 samples 4.5 MB), so the bound holds ~22 MB beyond the behaviours in play at most.
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from typing import Any

import numpy as np

# (through the engine: its compiled kernels load where a behaviour is trained to be played,
# at an engine's build, as before)
from behaviors.puppet_master.engine import Behavior

KEPT_SAMPLES = 16_000     # training samples; the five shipped behaviours are 12,400

_kept: OrderedDict[tuple, Behavior] = OrderedDict()
_lock = threading.Lock()     # the studio and the reloader train in worker threads


def _key(demo: Any, params: dict[str, Any]) -> tuple | None:
    try:
        a = np.ascontiguousarray(demo, dtype=np.float64)
    except (TypeError, ValueError):
        return None             # Behavior.train says what is wrong with it
    digest = hashlib.sha1(repr((a.shape, a.dtype.str)).encode() + a.tobytes()).hexdigest()
    # the type too: a window of 40 and of 40.0 are refused or taken alike, but each is its own
    return digest, tuple(sorted((k, type(v).__name__, repr(v)) for k, v in params.items()))


def train(demo: np.ndarray, /, **params: Any) -> Behavior:
    """:meth:`Behavior.train` of a demonstration read from a behaviour folder, kept: the same
    demonstration and parameters give the behaviour trained before. Raises as
    :meth:`Behavior.train` does (a refusal is not kept)."""
    key = _key(demo, params)
    if key is None:
        return Behavior.train(demo, **params)
    with _lock:
        behavior = _kept.get(key)
        if behavior is not None:
            _kept.move_to_end(key)
            return behavior
    behavior = Behavior.train(demo, **params)
    with _lock:
        _kept[key] = behavior
        _kept.move_to_end(key)
        while _kept and sum(b.samples for b in _kept.values()) > KEPT_SAMPLES:
            _kept.popitem(last=False)      # (one over the bound alone is not kept either)
    return behavior


def forget() -> None:
    """Drop every kept behaviour."""
    with _lock:
        _kept.clear()
