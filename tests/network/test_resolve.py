"""A receiver found by host name whose address changes (DHCP): the name is looked up again and
the datagrams follow it, without a restart. Real look-ups: the sender runs in a child with its
own mount namespace, where a hosts file the test rewrites is bound over /etc/hosts."""

from __future__ import annotations

import shutil
import socket
import subprocess
import sys
from pathlib import Path

import pytest

CHILD = r"""
import logging, signal, sys, threading, time
from tabletop.resolve import Destination
logging.basicConfig(level=logging.INFO, stream=sys.stderr)
Destination.REFRESH_S = 0.5          # (30 s in the installation)
started = 0
class Counted(threading.Thread):
    def start(self):
        global started
        if self.name.startswith("resolve:"):
            started += 1
        super().start()
threading.Thread = Counted
signal.signal(signal.SIGTERM, lambda *_: (print(f"resolve threads ever: {started}",
                                                file=sys.stderr, flush=True), sys.exit(0)))
d = Destination("sink", "tabletop-receiver", int(sys.argv[1]), logging.getLogger("tabletop"),
                blocking=False)
end = time.monotonic() + 30
while time.monotonic() < end:
    d.sendto(b"hello")
    time.sleep(0.02)
"""


def _can_bind_hosts(tmp_path: Path) -> bool:
    if shutil.which("unshare") is None:
        return False
    probe = tmp_path / "probe"
    probe.write_text("127.0.0.1 probe\n")
    r = subprocess.run(["unshare", "-m", "--propagation", "private", "sh", "-c",
                        f"mount --bind {probe} /etc/hosts"], capture_output=True)
    return r.returncode == 0


def _rewrite(hosts: Path, text: str) -> None:
    with open(hosts, "r+") as f:       # in place: the bound file is this inode
        f.write(text)
        f.truncate()


def test_a_receiver_whose_address_changes_is_reached_again(tmp_path):
    """The receiver's name first has one address; then a second, listed first, while the first
    stays (a multi-homed receiver): datagrams stay on the first, nothing "moved"; then only the
    second: they follow it, "moved" said once. One look-up thread, however many look-ups."""
    if not _can_bind_hosts(tmp_path):
        pytest.skip("no mount namespace to bind a hosts file in (needs unshare -m)")
    a = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    a.bind(("127.0.0.5", 0))
    port = a.getsockname()[1]
    b = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    b.bind(("127.0.0.6", port))
    a.settimeout(15.0)
    b.settimeout(15.0)
    hosts = tmp_path / "hosts"
    hosts.write_text("127.0.0.1 localhost\n127.0.0.5 tabletop-receiver\n")
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    child = subprocess.Popen(
        ["unshare", "-m", "--propagation", "private", "sh", "-c",
         f'mount --bind "{hosts}" /etc/hosts && exec "{sys.executable}" "{script}" {port}'],
        cwd=Path(__file__).resolve().parents[2], stderr=subprocess.PIPE, text=True)
    try:
        assert a.recv(64) == b"hello"      # the first address
        _rewrite(hosts, "127.0.0.1 localhost\n127.0.0.6 tabletop-receiver\n"
                        "127.0.0.5 tabletop-receiver\n")
        b.settimeout(3.0)                  # 6 look-ups at REFRESH_S 0.5
        with pytest.raises(socket.timeout):
            b.recv(64)
        assert a.recv(64) == b"hello"      # still the first address
        _rewrite(hosts, "127.0.0.1 localhost\n127.0.0.6 tabletop-receiver\n")
        b.settimeout(15.0)
        assert b.recv(64) == b"hello"      # the DHCP lease moved the receiver
    finally:
        child.terminate()
        _, err = child.communicate(timeout=30)
        a.close()
        b.close()
    assert err.count("moved") == 1, err
    assert "tabletop-receiver moved from 127.0.0.5 to 127.0.0.6" in err, err
    assert "resolve threads ever: 1" in err, err


def test_a_closed_thread_scheduled_late_leaves_the_new_threads_request():
    """Closed, then sent on: a new look-up thread is started and asked for a look-up. The closed
    thread, scheduled only now, wakes and ends: run here in its place (its function driven
    directly, with the request it was given), it must leave the new thread's request, which is
    then served (the name found again, no look-up left pending for ever)."""
    import logging
    import time

    from tabletop.resolve import Destination
    now = [0.0]
    d = Destination("sink", "localhost", 9, logging.getLogger("tabletop"),
                    clock=lambda: now[0])
    assert d.wait(10.0) is not None
    old_thread, old_due = d._thread, d._due
    d.close()
    old_thread.join(10.0)           # (the real one ended: its place is taken below)
    now[0] += 2 * Destination.REFRESH_S
    d.target()                      # a new thread, asked for a look-up
    assert d._thread is not None and d._thread is not old_thread
    old_due.set()                   # as close() left it for the closed thread
    d._serve(old_due)               # the closed thread, late: returns at once
    end = time.monotonic() + 30.0
    while d._looking and time.monotonic() < end:
        time.sleep(0.01)
    looking = d._looking
    d.close()
    assert not looking, "the new thread's look-up request was lost"
