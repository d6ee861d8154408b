"""The Puppet Master tests' shared setup: each shipped behaviour trained once per test worker.

The shipped library's demonstrations (behaviors/library) are trained by most of these tests:
through the plugin's build, demos.shipped and the tests' own calls, the same five
demonstrations with the same parameters were trained 267 times in one process running this
folder and tests/studio (11.7 CPU s beyond each one's first training, of the two folders'
~180). A Behavior is shared read-only by any number of
reactors (behavior.py), so while a test of this folder runs, Behavior.train gives the
behaviour trained before for the same shipped demonstration and parameters; any other
demonstration (synthetic, edited, a take) is trained afresh every time, as are calls that
raise. The first training of each runs the real code in every worker.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from behaviors.puppet_master.behavior import Behavior

LIBRARY = Path(__file__).resolve().parents[2] / "behaviors" / "library"
_train = Behavior.__dict__["train"].__func__
_shipped: set[str] = set()          # digests of the shipped demonstrations, read once
_trained: dict[tuple, Behavior] = {}


def _digest(a: np.ndarray) -> str:
    return hashlib.sha1(str((a.dtype.str, a.shape)).encode() + a.tobytes()).hexdigest()


def _shipped_digests() -> set[str]:
    if not _shipped:
        from tabletop.library import read_demonstration
        _shipped.update(_digest(np.ascontiguousarray(read_demonstration(p)))
                        for p in sorted(LIBRARY.glob("*/demonstration.csv")))
    return _shipped


def _train_once(cls: type, demo: Any, /, rate_hz: float = 40.0, window: int = 40,
                **params: Any) -> Behavior:
    a = demo if isinstance(demo, np.ndarray) else None
    if a is None or a.dtype != np.float64 or a.ndim != 2:
        return _train(cls, demo, rate_hz, window, **params)
    digest = _digest(np.ascontiguousarray(a))
    if digest not in _shipped_digests():
        return _train(cls, demo, rate_hz, window, **params)
    key = (cls, digest, repr(rate_hz), repr(window),
           tuple(sorted((k, type(v).__name__, repr(v)) for k, v in params.items())))
    if key not in _trained:
        _trained[key] = _train(cls, demo, rate_hz, window, **params)
    return _trained[key]


@pytest.fixture(autouse=True)
def shipped_behaviours_trained_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """Behavior.train keeps the shipped demonstrations' behaviours for this test (see above)."""
    monkeypatch.setattr(Behavior, "train", classmethod(_train_once))
