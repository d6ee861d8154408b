"""Shared fixtures: the learned models are built once per test session (about 3 s)."""

import fcntl
import os
from pathlib import Path

import numpy as np
import pytest

from behaviors.kernel_cache import SHARED
from behaviors.touch_pose.engine import TouchPose, learned_models


def cache_folder(tmp_path_factory) -> Path:
    """The test session's cache folder (an ``XDG_CACHE_HOME``), not the user's; shared by the
    pytest-xdist workers. Its compiled kernels are the ones every other test loads
    (``kernel_cache.SHARED``, linked): else each ``tabletop`` process a worker started once
    it had set this folder compiled the kernels again (10-30 CPU s each, until the run's own
    copy was filled)."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent          # the run's folder, above each worker's own
    folder = root / "touch_pose_models"
    kernels = folder / "tabletop" / "kernels"
    kernels.parent.mkdir(parents=True, exist_ok=True)
    if not kernels.is_symlink():
        try:
            os.makedirs(SHARED, exist_ok=True)
            kernels.symlink_to(SHARED, target_is_directory=True)
        except FileExistsError:     # (another worker's, at the same moment)
            pass
        except OSError:             # (no user cache: the kernels' own fallbacks, as outside)
            pass
    return folder


@pytest.fixture(scope="session")
def models_cache(tmp_path_factory) -> Path:
    """:func:`cache_folder`, for a process run by a test."""
    return cache_folder(tmp_path_factory)


@pytest.fixture(scope="session")
def models(tmp_path_factory):
    """Learned into (and kept in) :func:`cache_folder`. The pytest-xdist workers share it: the
    first learns and writes the cache file, the others wait for it and load it (identical
    models: tests/touch_pose/test_models_cache.py)."""
    folder = cache_folder(tmp_path_factory)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("XDG_CACHE_HOME", str(folder))
        with open(folder / "learning.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            learned = learned_models()
        yield learned


@pytest.fixture
def make(models):
    """A character factory (engines are closed at the end of the test)."""
    made = []

    def factory(view=(90.0, 15.0), physics=True, **kw):
        e = TouchPose(azimuth=view[0], elevation=view[1], physics=physics, models=models, **kw)
        made.append(e)
        return e

    yield factory
    for e in made:
        e.close()


def actions_begun(engine, path, times, rate=30.0, rest=0.1) -> set:
    """Rest on the path's start (table m) for ``rest`` s, drag it over ``times`` (s), lift;
    the actions begun."""
    begun, k = set(), 0
    while True:
        t = k / rate
        k += 1
        if t > rest + times[-1] + 1 / rate:
            return begun - {None}
        s = min(max(t - rest, 0.0), times[-1])
        r = engine.step(t, {1: (float(np.interp(s, times, path[:, 0])),
                                float(np.interp(s, times, path[:, 1])))})
        begun.add(r["action"])
