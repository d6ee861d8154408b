"""Behaviours trained from behaviour folders are kept for the process (behaviors/puppet_master/
kept.py): an engine built again on an unchanged folder (a kiosk's applied config edit) is not
trained again, a changed file is."""

from pathlib import Path

import numpy as np
import pytest

from behaviors.puppet_master import kept
from behaviors.puppet_master.engine import Behavior
from tabletop import library
from tests.puppet_master import demos
from tests.puppet_master.test_plugin import build


def _demo(seed: int) -> np.ndarray:
    """A 6 s demonstration (240 training samples): trained in a few milliseconds."""
    return demos.follow_behind(demos.main_path(seed, 6.0))


@pytest.fixture(autouse=True)
def trainings(monkeypatch) -> list:
    """Nothing kept before and after; each training made (by the real code, not this folder's
    train-once setup) listed."""
    made = []
    train = Behavior.__dict__["train"].__func__
    from tests.puppet_master import conftest

    def counted(cls, demo, /, **params):
        made.append(params.get("window"))
        return conftest._train(cls, demo, **params)

    assert train is conftest._train_once
    monkeypatch.setattr(Behavior, "train", classmethod(counted))
    kept.forget()
    yield made
    kept.forget()


def _same(a: Behavior, b: Behavior) -> bool:
    return (a.params == b.params and np.array_equal(a.step_table, b.step_table)
            and np.array_equal(a.situation_vectors, b.situation_vectors))


def _built(folder: Path, rate_hz: float | None = None) -> Behavior:
    (engine,) = build([{"kind": "puppet_master", "name": "pet", "behavior": str(folder),
                        "rate_hz": rate_hz, "main": {"puck": 1}}])
    return engine.behavior


def test_an_unchanged_folder_is_trained_once_and_a_changed_file_again(tmp_path, trainings):
    folder = library.save_behavior(tmp_path / "library", "pet", _demo(1), {"window": 40})
    first = _built(folder)
    again = _built(folder)
    assert again is first and len(trainings) == 1
    # one value of the demonstration edited on disk: trained afresh, as a fresh training
    csv = folder / "demonstration.csv"
    lines = csv.read_text().splitlines()
    cells = lines[100].split(",")
    cells[4] = repr(float(cells[4]) + 0.01)
    lines[100] = ",".join(cells)
    csv.write_text("\n".join(lines) + "\n")
    edited = _built(folder)
    stored = library.load_behavior(folder)
    assert len(trainings) == 2 and edited is not first and not _same(edited, first)
    assert _same(edited, Behavior.train(stored.demonstration, **stored.parameters))
    # a parameter edited in behavior.yaml: trained afresh with it
    yaml_file = folder / "behavior.yaml"
    text = yaml_file.read_text()
    assert "window: 40" in text
    yaml_file.write_text(text.replace("window: 40", "window: 41", 1))
    widened = _built(folder)
    assert len(trainings) == 4 and widened.params.window == 41   # (and the fresh one above)
    # the engine's own rate is a parameter too
    assert _built(folder, 30.0).params.rate_hz == 30.0 and len(trainings) == 5


def test_the_kept_behaviours_are_bounded_by_their_samples(monkeypatch, trainings):
    made = {k: _demo(k) for k in range(4)}
    first = {k: kept.train(made[k]) for k in range(3)}
    monkeypatch.setattr(kept, "KEPT_SAMPLES", sum(b.samples for b in first.values()) - 1)
    kept.train(made[0].copy())                       # the first, used last, then ...
    kept.train(made[3])                              # ... one more: the least recent go
    assert len(trainings) == 4
    assert kept.train(made[0]) is first[0] and len(trainings) == 4
    kept.train(made[1])
    assert len(trainings) == 5                       # the second trained again
