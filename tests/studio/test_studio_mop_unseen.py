"""A MOP take whose performer is a finger or a motion-capture stream that never arrives says so,
as a puck's take does (test_studio_mop.py): "recording: no finger" while it records, and
"finger unseen 1.0 s of 1.0 s" beside the take refused as too short."""

import numpy as np
import pytest

from tabletop.frames import Frame
from tabletop.plugins.mop_table import RATE, build, designer_config
from tabletop.studio.machine import Studio
from tabletop.studio.mop_target import MopTarget


@pytest.mark.parametrize("inputs, streams, said", [
    ([{"kind": "touch"}], {}, "finger"),
    ([{"kind": "stream", "name": "arm", "columns": [0, 1]}], {}, "stream arm"),
    ([{"kind": "stream", "name": "arm", "columns": [0, 1]}],     # one column: too short
     {"arm": np.zeros(1)}, "stream arm"),
])
def test_a_take_whose_finger_or_stream_never_arrives_says_so(tmp_path, inputs, streams, said):
    """Recording says "no <input>" and the take refused as too short names how long the input
    went unseen (without it, only "take too short (0 of 8 samples of motion)")."""
    cfg = designer_config(tmp_path)
    cfg["engines"][0]["performers"][0]["inputs"] = inputs
    del cfg["engines"][0]["characters"][0]["actions"]   # a puck's template: none to follow
    engine = build(cfg, tmp_path)
    studio = Studio([MopTarget(engine, c, tmp_path / "lib", background=False)
                     for c in engine.order], countdown_s=0.0)
    labels = []
    for seq in range(62):      # R, 1 s without the input, R
        cmds = ("designer.record",) if seq in (0, 61) else ()
        frame = studio(Frame(seq, seq / RATE, streams=dict(streams), commands=cmds,
                             focus="mop/face"))
        labels.append(frame.character("studio").label)
        engine.step(frame)
    assert f"recording: no {said}" in labels[30], labels[30]
    assert "too short" in labels[-1] and f"{said} unseen 1.0 s of 1.0 s" in labels[-1], \
        labels[-1]
