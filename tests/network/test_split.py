"""The split installation, end to end in two processes: a tracker process (synthetic camera ->
tracker -> ``tuio`` sink) and a stage process (``osc`` source -> ...), over loopback UDP."""

import json
import math
import signal
import subprocess
import sys
from pathlib import Path

import yaml

from tabletop.config import load_config

from tests import children
from tests.network.helpers import free_udp_port

ROOT = Path(__file__).resolve().parents[2]


def test_the_example_configs_are_valid():
    tracker = load_config(ROOT / "examples/split/tracker.yaml")
    stage = load_config(ROOT / "examples/split/stage.yaml")
    assert tracker["sinks"][0]["kind"] == "tuio"
    assert stage["sources"][0]["kind"] == "osc"
    assert tracker["sinks"][0]["port"] == stage["sources"][0]["port"]


def frames(path: Path) -> list[dict]:
    lines = path.read_text().splitlines()
    return [json.loads(line) for line in lines[1:]]


def run(config: Path, record: Path, seconds: float) -> subprocess.Popen:
    return children.popen([sys.executable, "-m", "tabletop", "run", "--config", str(config),
                           "--headless", "--seconds", str(seconds), "--record", str(record)],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def test_the_stage_reproduces_the_trackers_pucks(tmp_path):
    port = free_udp_port()
    base = {"table": {"width": 1.2, "height": 0.8}, "loop": {"rate_hz": 60},
            "view": {"enabled": False}}
    tracker_cfg = dict(base, sources=[{"kind": "synthetic_camera", "name": "camera",
                                       "pucks": [1, 2], "resolution": [640, 360], "fps": 60,
                                       "hands": {"every_s": 0}}],
                       sinks=[{"kind": "tuio", "name": "out", "port": port}])
    stage_cfg = dict(base, tracking={"smooth": False},
                     sources=[{"kind": "osc", "name": "tracker", "port": port}])
    (tmp_path / "tracker.yaml").write_text(yaml.safe_dump(tracker_cfg))
    (tmp_path / "stage.yaml").write_text(yaml.safe_dump(stage_cfg))
    stage = run(tmp_path / "stage.yaml", tmp_path / "stage.jsonl", 120)
    tracker = run(tmp_path / "tracker.yaml", tmp_path / "tracker.jsonl", 4)
    try:
        out, _ = tracker.communicate(timeout=120)
        assert tracker.returncode == 0, out
    finally:
        stage.send_signal(signal.SIGTERM)  # a clean stop: the recording is flushed complete
        stage_out, _ = stage.communicate(timeout=60)
    assert stage.returncode == 0, stage_out

    sent = [f for f in frames(tmp_path / "tracker.jsonl") if f["pucks"]]
    got = [f for f in frames(tmp_path / "stage.jsonl") if f["pucks"]]
    assert len(sent) > 60 and len(got) > 60
    # Every stage frame holds the pucks of one tracker frame (the newest it received).
    index = {}
    for f in sent:
        for p in f["pucks"]:
            index.setdefault(p["id"], []).append((p["x"], p["y"], p["angle"]))
    matched = 0
    for f in got:
        ok = True
        for p in f["pucks"]:
            cands = index.get(p["id"], [])
            ok &= any(abs(x - p["x"]) <= 1e-6 and abs(y - p["y"]) <= 1e-6
                      and abs(math.remainder(a - p["angle"], math.tau)) <= 1e-6
                      for x, y, a in cands)
        matched += ok
    assert matched >= 0.95 * len(got), f"{matched} of {len(got)} stage frames matched"
    assert {p["id"] for f in got for p in f["pucks"]} == {1, 2}


def test_bad_network_options_are_one_clear_line():
    import pytest

    from tabletop.config import validate_config
    from tabletop.schema import ConfigError

    cases = [
        ({"kind": "osc", "host": "localhost"}, "sources[0].host", "an IP address"),
        ({"kind": "osc", "port": 70000}, "sources[0].port", "out of range"),
        ({"kind": "osc", "allow": ["10.0.0.300"]}, "sources[0].allow[0]", "an IP address"),
        # as `tabletop status` and URLs write it: the hint names the bare form
        ({"kind": "osc", "host": "[::1]"}, "sources[0].host",
         "got '[::1]' (an IPv6 address is written bare here: ::1)"),
        ({"kind": "serial"}, "sources[0].port", "missing"),
        ({"kind": "serial", "port": "loop://", "timeout_s": 0}, "sources[0].timeout_s",
         "out of range"),
    ]
    for source, where, what in cases:
        with pytest.raises(ConfigError) as info:
            validate_config({"sources": [source]}, "cfg.yaml")
        assert f"cfg.yaml: {where}:" in str(info.value) and what in str(info.value)
    with pytest.raises(ConfigError, match=r"sinks\[0\].characters.lover: expected an integer"):
        validate_config({"sources": [{"kind": "serial", "port": "loop://"}],
                         "sinks": [{"kind": "tuio", "characters": {"lover": "x"}}]}, "cfg.yaml")


def test_a_destination_that_can_never_be_reached_is_refused_at_load():
    """A TUIO sink sending to port 0, or a sink or heartbeat host that is not an address or a
    host name at all ("my host"), ran and lost every datagram (the heartbeat said so only at
    debug level): refused at load, naming the key."""
    import pytest

    from tabletop.config import validate_config
    from tabletop.schema import ConfigError

    src = [{"kind": "scripted", "name": "a"}]
    cases = [
        ({"sources": src, "sinks": [{"kind": "tuio", "port": 0}]}, "sinks[0].port",
         "out of range"),
        ({"sources": src, "sinks": [{"kind": "tuio", "host": "not a host"}]}, "sinks[0].host",
         "host name"),
        ({"sources": src, "kiosk": {"heartbeat": {"host": "my host"}}}, "kiosk.heartbeat.host",
         "host name"),
    ]
    for cfg, where, what in cases:
        with pytest.raises(ConfigError) as info:
            validate_config(cfg, "cfg.yaml")
        assert f"cfg.yaml: {where}:" in str(info.value) and what in str(info.value), info.value
    for host in ("10.0.0.255", "table-7.local", "::1", "localhost", "gallery.example.org"):
        validate_config({"sources": src, "sinks": [{"kind": "tuio", "host": host}],
                         "kiosk": {"heartbeat": {"host": host}}}, "cfg.yaml")


def test_a_port_this_installation_already_uses_is_refused_at_load():
    """Two osc sources on one port (the second retried for ever: 'Address already in use'),
    and a tuio sink sending to the installation's own osc source (every puck came back as a
    second sighting and every character as a puck: a feedback loop)."""
    import pytest

    from tabletop.config import validate_config
    from tabletop.schema import ConfigError

    src = [{"kind": "scripted", "name": "a"}, {"kind": "osc", "name": "in", "port": 3400}]
    cases = [
        ({"sources": src + [{"kind": "osc", "name": "in2", "host": "0.0.0.0", "port": 3400}]},
         "cfg.yaml: sources[2].port: port 3400 is also sources[1]'s; only one socket can "
         "listen on it: give another"),
        ({"sources": src, "sinks": [{"kind": "tuio", "host": "localhost", "port": 3400}]},
         "cfg.yaml: sinks[0].port: localhost:3400 is this installation's own sources[1] (osc): "
         "its pucks and characters would come back as pucks; send to another port or machine"),
    ]
    for cfg, message in cases:
        with pytest.raises(ConfigError) as info:
            validate_config(cfg, "cfg.yaml")
        assert str(info.value) == message
    validate_config({"sources": src + [{"kind": "osc", "name": "in2", "port": 3401}],
                     "sinks": [{"kind": "tuio", "port": 3402},
                               {"kind": "tuio", "name": "far", "host": "10.0.0.7", "port": 3400}]},
                    "cfg.yaml")


def test_a_kiosk_heartbeat_sent_to_its_own_osc_source_is_refused(tmp_path):
    """The heartbeat sent to the installation's own osc source arrived there every second as
    an unknown message: logged on and on, "ignored: N unknown address" in that source's
    health, and no monitor heard the table. Refused in a kiosk config, and when a config is
    run with --kiosk; a config that runs no kiosk never sends one."""
    import subprocess
    import sys

    import pytest

    from tabletop.config import validate_config
    from tabletop.schema import ConfigError

    src = [{"kind": "scripted", "name": "a"}, {"kind": "osc", "name": "in", "port": 3400}]
    own = {"host": "localhost", "port": 3400}
    with pytest.raises(ConfigError) as info:
        validate_config({"sources": src, "kiosk": {"enabled": True, "heartbeat": own}},
                        "cfg.yaml")
    assert str(info.value) == (
        "cfg.yaml: kiosk.heartbeat.port: localhost:3400 is this installation's own sources[1] "
        "(osc): the heartbeats would arrive there as unknown messages; send them to another "
        "port or machine")
    for kiosk in ({"heartbeat": own},                                    # no kiosk: nothing sent
                  {"enabled": True, "heartbeat": dict(own, enabled=False)},
                  {"enabled": True, "heartbeat": dict(own, port=3401)},
                  {"enabled": True, "heartbeat": dict(own, host="10.0.0.7")}):
        validate_config({"sources": src, "kiosk": kiosk}, "cfg.yaml")
    cfg = tmp_path / "cfg.yaml"
    cfg.write_text("sources:\n  - {kind: scripted, name: a}\n"
                   "  - {kind: osc, name: in, port: 3400}\n"
                   "engines: []\nkiosk: {heartbeat: {port: 3400}}\n")
    run = subprocess.run([sys.executable, "-m", "tabletop", "run", "--config", str(cfg),
                          "--headless", "--kiosk", "--seconds", "1"],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run.stderr
    assert run.stderr.strip() == (f"tabletop run: error: {cfg}: kiosk.heartbeat.port: "
                                  "127.0.0.1:3400 is this installation's own sources[1] (osc): "
                                  "the heartbeats would arrive there as unknown messages; send "
                                  "them to another port or machine")
