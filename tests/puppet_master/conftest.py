"""The Puppet Master tests' shared setup: each shipped behaviour read and trained once per test
worker.

The shipped library's demonstrations (behaviors/library) are trained by most of these tests:
through the plugin's build, demos.shipped and the tests' own calls, the same five
demonstrations with the same parameters were trained 267 times in one process running this
folder and tests/studio (11.7 CPU s beyond each one's first training, of the two folders'
~180). A Behavior is shared read-only by any number of
reactors (behavior.py), so while a test of this folder runs, Behavior.train gives the
behaviour trained before for the same shipped demonstration and parameters; any other
demonstration (synthetic, edited, a take) is trained afresh every time, as are calls that
raise. The first training of each runs the real code in every worker.

Likewise the shipped folders are read once (tabletop.library.load_behavior: 15-25 ms each, its
CSV and YAML parsed; the plugin's build alone read them 57 times in test_pm_together.py): a
read of a folder of behaviors/library whose files are unchanged (names, sizes, times) gives a
copy of the first read (its own parameters and demonstration, which a test may change); any
other folder (a test's own library, a copy) is read afresh every time.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from behaviors.puppet_master.behavior import Behavior
from tabletop import library

LIBRARY = Path(__file__).resolve().parents[2] / "behaviors" / "library"
_train = Behavior.__dict__["train"].__func__
_shipped: set[str] = set()          # digests of the shipped demonstrations, read once
_trained: dict[tuple, Behavior] = {}
_load_behavior = library.load_behavior
_read: dict[tuple, library.StoredBehavior] = {}


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


def _load_once(folder: Any, *args: Any, **kwargs: Any) -> library.StoredBehavior:
    path = Path(folder).resolve()
    if path.parent != LIBRARY or not path.is_dir():
        return _load_behavior(folder, *args, **kwargs)
    key = (str(path), str(folder), tuple(sorted(
        (e.name, e.stat().st_mtime_ns, e.stat().st_size) for e in os.scandir(path))))
    if key not in _read:
        _read[key] = _load_behavior(folder, *args, **kwargs)
    stored = _read[key]
    return dataclasses.replace(stored, parameters=copy.deepcopy(stored.parameters),
                               demonstration=stored.demonstration.copy(),
                               extra=copy.deepcopy(stored.extra))


@pytest.fixture(autouse=True)
def shipped_folders_read_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """library.load_behavior keeps the shipped folders' reads for this test (see above)."""
    monkeypatch.setattr(library, "load_behavior", _load_once)
