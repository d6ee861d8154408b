"""DESIGN.md's network contracts and the session recording's names, read as outside scripts read
them: a real ``tabletop run`` process fed TUIO 1.1 and ``/mocap`` over loopback UDP, its ``tuio``
sink caught by a python-osc server, its recording read as raw JSON lines."""

import json
import math
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from tests import children
from tests.network.helpers import Receiver, RefSender, bundle, free_udp_port, message

ROOT = Path(__file__).resolve().parents[2]
TABLE = (1.2, 0.8)
PUCK = (10, 1, 0.25, 0.5, 0.5)           # session, class id (marker 1), x, y, angle (TUIO)
CURSOR = (3, 0.5, 0.75)                  # session (the touch id), x, y
BLOB = (4, 0.1, 0.2)


def by_command(packet):
    """{command: [params...]} of one TUIO bundle."""
    out = {}
    for _address, params in packet:
        out.setdefault(params[0], []).append(params[1:])
    return out


def send_state(ref: RefSender) -> None:
    """One frame of every profile as the reference server sends it, and one mocap vector."""
    ref.objects([PUCK])
    ref.cursors([CURSOR])
    s, x, y = BLOB
    ref.send(bundle(message("/tuio/2Dblb", "alive", s),
                    message("/tuio/2Dblb", "set", s, x, y, 0.0, 0.05, 0.05, 0.01, 0.0, 0.0, 0.0,
                            0.0, 0.0),
                    message("/tuio/2Dblb", "fseq", ref.fseq)))
    ref.send(message("/mocap/hand", 0.25, -1.5, 3.0))


def sink_saw_everything(receiver: Receiver) -> bool:
    """The sink has sent the puck, the character and both touches in one frame."""
    objects = [by_command(p) for p in list(receiver.packets) if p and p[0][0] == "/tuio/2Dobj"]
    cursors = [by_command(p) for p in list(receiver.packets) if p and p[0][0] == "/tuio/2Dcur"]
    return (any({s[1] for s in b.get("set", [])} == {1, 40} for b in objects)
            and any(len(b.get("set", [])) == 2 for b in cursors))


def test_a_run_takes_tuio_and_mocap_in_sends_tuio_out_and_records_the_contract_names(tmp_path):
    port = free_udp_port()
    receiver = Receiver()
    cfg = {"table": {"width": TABLE[0], "height": TABLE[1]}, "loop": {"rate_hz": 60},
           "view": {"enabled": False}, "tracking": {"smooth": False},
           "sources": [{"kind": "osc", "name": "net", "port": port}],
           "engines": [{"kind": "puppet_master", "name": "lover",
                        "behavior": str(ROOT / "behaviors/library/lover"), "main": {"puck": 1}}],
           "sinks": [{"kind": "tuio", "name": "out", "port": receiver.port,
                      "characters": {"lover": 40}}]}
    (tmp_path / "io.yaml").write_text(yaml.safe_dump(cfg))
    record = tmp_path / "session.jsonl"
    proc = children.popen([sys.executable, "-m", "tabletop", "run", "--config",
                           str(tmp_path / "io.yaml"), "--headless", "--seconds", "120",
                           "--record", str(record)], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True,
                          env=dict(os.environ, SDL_VIDEODRIVER="dummy"))
    ref = RefSender(port)
    try:
        end = time.monotonic() + 90.0    # start-up on a loaded machine, then a few frames
        while time.monotonic() < end and proc.poll() is None:
            send_state(ref)
            if sink_saw_everything(receiver) and len(receiver.packets) > 40:
                break
            time.sleep(1 / 30)
    finally:
        proc.send_signal(signal.SIGTERM)   # a clean stop: the recording is complete
        out, _ = proc.communicate(timeout=60)
        receiver.close()
    assert proc.returncode == 0, out
    assert sink_saw_everything(receiver), out

    # --- the recording, as raw JSON: the names DESIGN.md promises outside scripts
    lines = record.read_text().splitlines()
    header = json.loads(lines[0])
    assert header["format"] == "tabletop-session" and isinstance(header["version"], int)
    assert header["config"]["sources"][0]["kind"] == "osc" and "calibration" in header
    frames = [json.loads(line) for line in lines[1:]]
    assert frames[0]["t"] == 0.0
    for f in frames:
        assert {"seq", "t", "pucks", "touches", "streams", "characters"} <= set(f)
    full = [f for f in frames if f["pucks"] and len(f["touches"]) == 2 and f["streams"]]
    assert full, "no recorded frame holds the puck, both touches and the stream"
    f = full[-1]
    (p,) = f["pucks"]
    assert p["id"] == 1 and p["state"] == "seen"          # the class id is the marker id
    # x * W, (1 - y) * H; the angle clockwise on screen -> counter-clockwise on the table
    assert (p["x"], p["y"], p["angle"]) == pytest.approx((0.3, 0.4, -0.5), abs=1e-6)
    touches = {c["id"]: (c["x"], c["y"]) for c in f["touches"]}   # session id = touch id
    assert touches[3] == pytest.approx((0.6, 0.2), abs=1e-6)
    assert touches[4] == pytest.approx((0.12, 0.64), abs=1e-6)
    assert f["streams"] == {"hand": [0.25, -1.5, 3.0]}
    (c,) = f["characters"]
    assert c["name"] == "lover" and all(math.isfinite(c[k]) for k in ("x", "y", "heading"))

    # --- the tuio sink: one bundle per profile and frame, the reference's order, the default
    # source name, rising fseq, class id = puck id, the inverse mapping, stable session ids
    objects = [by_command(pk) for pk in receiver.packets if pk[0][0] == "/tuio/2Dobj"]
    cursors = [by_command(pk) for pk in receiver.packets if pk[0][0] == "/tuio/2Dcur"]
    assert all({a for a, _ in pk} == {pk[0][0]} for pk in receiver.packets)  # one profile each
    for b in objects + cursors:
        assert list(b)[:2] == ["source", "alive"] and list(b)[-1] == "fseq"
        assert b["source"] == [[f"tabletop@{socket.gethostname()}"]]
        assert sorted(s[0] for s in b.get("set", [])) == sorted(b["alive"][0])
    fseqs = [b["fseq"][0][0] for b in objects]
    assert all(b > a for a, b in zip(fseqs, fseqs[1:])) and fseqs[0] > 0
    assert [b["fseq"][0][0] for b in cursors] == fseqs     # the same frame, the same fseq
    puck_sets = [s for b in objects for s in b.get("set", []) if s[1] == 1]
    assert len({s[0] for s in puck_sets}) == 1              # one session while it stays
    s, cls, x, y, a = puck_sets[-1][:5]
    assert (x, y, a) == pytest.approx((0.25, 0.5, 0.5), abs=1e-6)
    both = [b["set"] for b in cursors if len(b.get("set", [])) == 2]
    by_place = {(round(x, 5), round(y, 5)): sid for sets in both for sid, x, y, *_ in sets}
    assert set(by_place) == {(0.5, 0.75), (0.1, 0.2)} and len(set(by_place.values())) == 2
