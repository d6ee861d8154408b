"""The supervisor's "restarting" after a crash goes out as a heartbeat too: a gallery watching
``tabletop status`` saw a kiosk whose installation crashed fall silent until it came back (or
for ever, when every start fails); only the status file said "restarting"."""

import json
import sys
import threading

from tabletop.commands.status import format_heartbeat
from tabletop.kiosk.health import Heartbeat
from tabletop.kiosk.supervisor import Policy, Supervisor
from tests.kiosk.test_health import OscListener
from tracking.scenes import wait_for


def test_a_restart_is_sent_as_a_heartbeat(tmp_path):
    osc = OscListener()
    failing = [sys.executable, "-c", "import sys; print('tabletop run: error: boom', "
               "file=sys.stderr); sys.exit(2)"]
    sup = Supervisor(failing, Policy(backoff_s=(5.0, 5.0), startup_s=60),
                     tmp_path / "crashes.log", echo=False, spares=0, name="table-3",
                     heartbeat=Heartbeat("127.0.0.1", osc.port))
    th = threading.Thread(target=sup.run)
    th.start()
    try:
        assert wait_for(lambda: len(osc.got) >= 1, 30.0)
    finally:
        sup.stop.set()
        th.join(30)
        osc.close()
    name, uptime, fps, unhealthy, text = osc.got[0]
    status = json.loads(text)
    assert name == "table-3" and status["mode"] == "restarting" and status["restarts"] == 1
    assert status["crash"].endswith(": tabletop run: error: boom") and status["pid"] is None
    assert format_heartbeat("127.0.0.1:1", name, uptime, fps, unhealthy, text).endswith(
        "0.0 fps  0 unhealthy  restarting  restarts 1")
