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
import logging, sys, time
from tabletop.resolve import Destination
logging.basicConfig(level=logging.INFO, stream=sys.stderr)
Destination.REFRESH_S = 0.5          # (30 s in the installation)
d = Destination("sink", "tabletop-receiver", int(sys.argv[1]), logging.getLogger("tabletop"),
                blocking=False)
end = time.monotonic() + 20
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


def test_a_receiver_whose_address_changes_is_reached_again(tmp_path):
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
        with open(hosts, "r+") as f:       # in place: the bound file is this inode
            f.write("127.0.0.1 localhost\n127.0.0.6 tabletop-receiver\n")
        assert b.recv(64) == b"hello"      # the DHCP lease moved the receiver
    finally:
        child.terminate()
        _, err = child.communicate(timeout=30)
        a.close()
        b.close()
    assert "tabletop-receiver moved from 127.0.0.5 to 127.0.0.6" in err, err
