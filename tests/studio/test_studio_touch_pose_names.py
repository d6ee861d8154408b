"""The names a touch-pose engine's studio takes are kept under: an engine name no folder may
have, one too long for a numbered name, and a name another run kept meanwhile."""

import json

import numpy as np

from tabletop.studio.machine import Studio
from tabletop.studio.pose_target import TouchPoseTarget
from tests.studio.test_studio_touch_pose import Poser, played
from tests.touch_pose.conftest import models  # noqa: F401  (the learned models, once)


def test_an_engine_whose_name_no_folder_may_have_keeps_its_takes(tmp_path, models):
    """A take of a touch-pose engine named "mein Poser" was refused when it stopped ("behaviour
    name 'mein Poser-action' is not usable"): every take it recorded was lost."""
    p = Poser(tmp_path, models)
    p.cfg["engines"][0]["name"] = "mein Poser"
    p.engine = p.build()
    p.target = TouchPoseTarget(p.engine)
    p.target._poller.every_s = 0.0
    p.studio = Studio([p.target], countdown_s=0.0)
    p.take()
    assert p.studio.state == "trying" and "trained action: its right hand" in p.status
    p.tick(cmds=["designer.keep"])
    assert "kept as action" in p.status and p.target.items() == ["action"]


def test_an_engine_with_a_long_name_keeps_take_after_take_within_the_name_rule(tmp_path, models):
    """An engine named with 57 characters makes ``NAME-action`` of 64: the second keep's name
    is shortened to leave room for its number within the library's rule (1-64 characters; F2
    refuses a name past it, ``NAME-action-2`` would be 66), as a behaviour's is."""
    from tabletop import library
    long_name = "p" * 57
    p = Poser(tmp_path, models)
    p.cfg["engines"][0]["name"] = long_name
    p.engine = p.build()
    p.target = TouchPoseTarget(p.engine)
    p.target._poller.every_s = 0.0
    p.studio = Studio([p.target], countdown_s=0.0)
    kept = []
    for _ in range(3):
        p.take()
        p.tick(cmds=["designer.keep"])
        assert "kept as " in p.status, p.status
        kept.append(p.status.split("kept as ", 1)[1].split()[0])
    assert kept[0] == f"{long_name}-action" and len(set(kept)) == 3
    assert all(library.NAME_RE.match(n) and len(n) <= 64 for n in kept), [len(n) for n in kept]
    assert sorted(kept) == p.target.items()
    assert kept[1:] == [f"{long_name}-acti-2", f"{long_name}-acti-3"]


def back(u: float) -> np.ndarray:
    """Another designer's drag: back and a little down."""
    return np.array([-0.08 * u, -0.03 * u])


def taken_meanwhile(tmp_path, models):
    """Two runs (A and B) on one library, each trying a take named poser-action; A keeps its
    take and B's watcher sees it. Returns (B, B's take's action)."""
    a, b = Poser(tmp_path, models), Poser(tmp_path, models)
    a.take()
    b.take(path=back)
    assert "trained poser-action" in b.status
    tried = b.target.pending
    a.tick(cmds=["designer.keep"])
    assert "kept as poser-action" in a.status
    b.tick()
    return b, tried


def test_a_take_whose_name_another_run_kept_meanwhile_is_kept_under_the_next_name(
        tmp_path, models):
    """Another run on the library kept its poser-action while this run's was tried: the
    watcher put that action over the one tried here (the drag played the other's), and K was
    refused ("an action of that name already exists") for as long as the take was tried."""
    b, tried = taken_meanwhile(tmp_path, models)
    known = {a.name: a for a in b.engine.core.m.actions}
    assert known["poser-action"] is tried                 # the take is tried on
    b.tick(cmds=["designer.keep"])
    assert "kept as poser-action-2" in b.status and b.studio.state == "idle", b.status
    assert b.target.items() == ["poser-action", "poser-action-2"]
    known = {a.name: a for a in b.engine.core.m.actions}
    assert known["poser-action-2"] is tried and known["poser-action"] is not tried
    stored = json.loads((tmp_path / "actions" / "poser-action-2" / "action.json").read_text())
    assert len(stored["times"]) == len(b.target.times)
    again = Poser(tmp_path, models)
    assert {"poser-action", "poser-action-2"} <= {a.name for a in again.engine.core.m.actions}


def test_a_discarded_take_gives_way_to_the_other_runs_action_of_its_name(tmp_path, models):
    b, tried = taken_meanwhile(tmp_path, models)
    b.tick(cmds=["designer.discard"])
    known = {a.name: a for a in b.engine.core.m.actions}
    assert "poser-action" in known and known["poser-action"] is not tried


def test_a_keep_refused_for_its_name_knows_the_other_runs_action_of_that_name(tmp_path, models):
    """Another run kept poser-action after this run's watcher last looked: this run's take was
    kept as poser-action-2, but the other action was never known (until the library changed
    again)."""
    a, b = Poser(tmp_path, models), Poser(tmp_path, models)
    a.take()
    b.take(path=back)
    b.target._poller.every_s = 1e9          # B's watcher has not looked since A's keep
    a.tick(cmds=["designer.keep"])
    assert "kept as poser-action" in a.status
    b.tick(cmds=["designer.keep"])
    assert "kept as poser-action-2" in b.status
    b.target._poller.every_s = 0.0
    for _ in range(5):
        b.tick()
    names = sorted(x.name for x in b.engine.core.m.actions if x.name.startswith("poser"))
    assert names == ["poser-action", "poser-action-2"]
