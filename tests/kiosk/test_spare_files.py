"""A warm spare prepared before a technician broke, fixed or replaced a file its config names
(a MOP template, a behaviour): at its go it builds again from the files as they are, so its
engines play what its recording's header carries and the recording replays."""

import shutil

from tabletop.kiosk import spare
from tests.kiosk.test_bad_action_start import GESTURES, _config
from tests.kiosk.test_supervisor import ROOT, drill_config


def test_a_spare_builds_again_when_a_template_it_read_changed(tmp_path):
    path = _config(tmp_path)
    prepared = spare.prepare(path)
    assert prepared is not None and prepared.current()
    with open(tmp_path / "line.csv", "a") as f:      # the technician breaks the template
        f.write("1e3,0.5\n")
    assert not prepared.current()
    assert prepared.changed() == str(tmp_path / "line.csv")
    prepared = spare.prepare(path)        # (refused: the kiosk's own start goes without it)
    assert prepared is None
    shutil.copy(GESTURES / "line.csv", tmp_path / "line.csv")
    prepared = spare.prepare(path)
    assert prepared is not None and prepared.current()
    (tmp_path / "line.csv").unlink()      # then makes it a folder
    (tmp_path / "line.csv").mkdir()
    assert not prepared.current()
    assert prepared.changed() == str(tmp_path / "line.csv")


def test_a_spare_builds_again_when_a_behaviour_file_changed(tmp_path):
    shutil.copytree(ROOT / "behaviors" / "library" / "lover", tmp_path / "lover")
    path = drill_config(tmp_path, [])
    path.write_text(path.read_text().replace(str(ROOT / "behaviors" / "library" / "lover"),
                                             "lover"))
    prepared = spare.prepare(path)
    assert prepared is not None and prepared.current()
    demo = tmp_path / "lover" / "demonstration.csv"
    demo.write_text(demo.read_text()[:200])
    assert not prepared.current()
    assert prepared.changed() == str(tmp_path / "lover")
