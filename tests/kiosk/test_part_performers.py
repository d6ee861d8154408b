"""The MOP performers' state a later recording part carries (tabletop.parts.part_states):
it survives JSON to the last bit, and one that is not the engine's is refused naming it."""

import json

import pytest

from bench.action_reload import _stage
from tabletop.frames import Frame, Puck
from tabletop.parts import part_states, resume_parts


def test_a_resting_performer_is_carried_to_a_fresh_stage_exactly(tmp_path):
    live = _stage(tmp_path)
    for k in range(60):                      # still for 2 s: it rests where it settled
        live.step(Frame(seq=k, t=10.0 + k / 60, pucks=(Puck(1, 0.5 + 1e-4 * (k % 2), 0.4,
                                                            0.3),)))
    states = json.loads(json.dumps(part_states([live])))
    fresh = _stage(tmp_path)
    assert not fresh.performers["hand"].resting
    resume_parts([fresh], states)
    assert fresh.performers["hand"].resting and fresh.part_state() == live.part_state()


@pytest.mark.parametrize("states, said", [
    ({"mop": {"hand": []}}, "engine 'mop': performer 'hand': expected the states of its 1"),
    ({"mop": {"hand": [[1.0, 2.0]]}}, "engine 'mop': a puck path's state is 17 finite numbers"),
    ({"mop": {"hand": [[float("nan")] * 17]}}, "17 finite numbers"),
    ([1], "expected a mapping of engines"),
])
def test_a_damaged_performers_state_is_refused_naming_the_engine(tmp_path, states, said):
    with pytest.raises(ValueError) as exc:
        resume_parts([_stage(tmp_path)], states)
    assert said in str(exc.value) and "\n" not in str(exc.value)
