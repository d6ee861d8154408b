"""A stored designed action (``<library>/<name>/action.json``) with numbers no take has is
refused naming its file and frame, never loaded with only numpy's overflow warning."""

import json

import numpy as np
import pytest

from behaviors.touch_pose.designed import FILE, DesignedActionError, load_action, to_json
from behaviors.touch_pose.humanoid import Humanoid, Pose


@pytest.fixture(scope="module")
def body():
    return Humanoid()


def _stored(body) -> dict:
    """A take of 40 frames over 2 s: the character standing, its root moving 0.3 m along x."""
    rots = np.tile([1.0, 0.0, 0.0, 0.0], (len(body.names), 1))
    poses = [Pose(np.array([0.3 * k / 40, 0.0, 0.9]), rots) for k in range(40)]
    return json.loads(to_json("a", "pelvis", np.linspace(0.0, 2.0, 40), poses))


@pytest.mark.parametrize("change, words", [
    (lambda d: d["root"][5].__setitem__(0, 1e300), "frame 6: root [1e+300, 0.0, 0.9] is beyond "
                                                   "1000 m"),
    (lambda d: d["times"].__setitem__(-1, 1e300), "the take lasts 1e+300 s; at most 3600 s"),
    (lambda d: d["rots"][7][2].__setitem__(1, 1e300), "frame 8: a rotation of length inf"),
    (lambda d: d["rots"][7][2].__setitem__(0, 0.0), "frame 8: a rotation of length 0"),
    # an empty take (or times not a list) stopped the installation's start with an IndexError
    (lambda d: d.update(times=[], root=[], rots=[]), "times must be a list of numbers"),
    (lambda d: d.update(times=[d["times"]]), "times must be a list of numbers"),
])
def test_a_stored_action_with_numbers_no_take_has_is_refused(tmp_path, body, change, words):
    d = _stored(body)
    (tmp_path / "ok").mkdir()
    (tmp_path / "ok" / FILE).write_text(json.dumps(d))
    assert load_action(tmp_path / "ok", body).duration == pytest.approx(2.0)
    change(d)
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / FILE).write_text(json.dumps(d))
    with pytest.raises(DesignedActionError) as err:
        load_action(tmp_path / "bad", body)
    assert str(err.value).startswith(f"{tmp_path / 'bad' / FILE}: ") and words in str(err.value)
