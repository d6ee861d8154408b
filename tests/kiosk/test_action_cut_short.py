"""A kiosk whose MOP template is cut short while its action plays (a copy interrupted inside the
last row's last value, which still reads as a number): the cut is listed with its file and
line, and the characters play the action from its last good version."""

import numpy as np

from tabletop.kiosk.simulate import SimClock
from tests.kiosk.running import kiosk_built, ticked_with_edits
from tests.kiosk.test_bad_action_start import drawing_config


def test_a_template_cut_inside_its_last_value_keeps_its_last_good_version(tmp_path):
    cfg_path, good = drawing_config(tmp_path)
    clock = SimClock()
    inst, refused = kiosk_built(cfg_path, clock=clock)
    assert refused is None
    stage = inst.engines[0]
    before = {n: stage.templates[n]["line"][1].copy() for n in ("walker", "lone")}
    cut = good["line.csv"].rstrip("\n")[:-2]     # its last value '-0.001098' cut to '-0.0010'
    ticked_with_edits(inst, clock, 60, {10: (tmp_path / "line.csv", cut)})
    last = len(good["line.csv"].splitlines())
    for name, samples in before.items():
        assert np.array_equal(stage.templates[name]["line"][1], samples), name
    said = [e for e in stage.start_problems if "line.csv" in e]
    assert len(said) == 2 and all(f"line.csv: line {last}: " in e and "cut short" in e
                                  for e in said), stage.start_problems
