"""A warm spare prepared before a technician broke, fixed or replaced a file its config names
(a MOP template, a behaviour): at its go it builds again from the files as they are, so its
engines play what its recording's header carries and the recording replays."""

import os
import shutil
import subprocess
import sys

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


def test_a_spare_says_in_the_kiosk_log_which_file_changed_since_it_was_prepared(tmp_path):
    """A real spare process (the supervisor's environment, its go on stdin): the template is
    replaced while it waits for its go; the line naming it goes to the kiosk's log, set up
    only by the installation's start (logged before, an INFO line went nowhere)."""
    path = _config(tmp_path)
    script = (
        "import shutil, sys\n"
        "class Go:\n"
        "    def readline(self):\n"             # the technician's copy, then the go
        f"        shutil.copy({str(GESTURES / 'circle.csv')!r}, {str(tmp_path / 'line.csv')!r})\n"
        "        return 'go 1\\n'\n"
        "sys.stdin = Go()\n"
        "from tabletop.cli import main\n"
        f"sys.exit(main(['run', '--config', {str(path)!r}, '--kiosk', '--headless', "
        "'--seconds', '1']))\n")
    env = dict(os.environ, TABLETOP_WAIT_GO="1", TABLETOP_SUPERVISED="1",
               TABLETOP_SUPERVISOR_PID=str(os.getpid()))
    done = subprocess.run([sys.executable, "-c", script], env=env, cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    log = (tmp_path / "logs" / "tabletop.log").read_text()
    said = [line for line in log.splitlines() if "since it was prepared" in line]
    assert len(said) == 1 and f"spare: {tmp_path / 'line.csv'} changed" in said[0], log[-2000:]
    assert "INFO" in said[0]
