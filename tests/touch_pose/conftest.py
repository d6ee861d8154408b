"""Shared fixtures: the learned models are built once per test session (about 3 s)."""

import fcntl
import os
from pathlib import Path

import numpy as np
import pytest

from behaviors.touch_pose.engine import TouchPose, learned_models


def cache_folder(tmp_path_factory) -> Path:
    """The test session's cache folder (an ``XDG_CACHE_HOME``), not the user's; shared by the
    pytest-xdist workers."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent          # the run's folder, above each worker's own
    folder = root / "touch_pose_models"
    folder.mkdir(exist_ok=True)
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


def stroke_drag(engine, models, name, pace=1.0, frac=1.0, hold=0.0, after=3.0, rate=30.0,
                before=0.0):
    """Drag the primary part of action ``name`` along its projected stroke at ``pace`` times
    its recorded duration (``frac`` of it), hold the finger ``hold`` s, lift, run ``after`` s;
    ``before`` s of resting on the part come first.
    Returns the output records, and the target (before tracking) and output rotations per step."""
    desc = engine.describe()
    traj = np.array(next(a for a in desc["actions"] if a["name"] == name)["trajectory"])
    act = next(a for a in models.actions if a.name == name)
    times = act.stroke_t * pace + before
    end = before + (times[-1] - before) * frac
    out, targets, outputs = [], [], []
    k, t = 0, 0.0
    while t <= end + hold + after:
        t = k / rate
        k += 1
        if t <= end + hold:
            s = min(t, end)
            touches = {1: (float(np.interp(s, times, traj[:, 0])),
                           float(np.interp(s, times, traj[:, 1])))}
        else:
            touches = {}
        out.append(engine.step(t, touches))
        targets.append(engine.target.rots.copy())
        outputs.append(engine.output.rots.copy())
    return out, targets, outputs


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
