"""Every shipped config, recorded live for a few seconds, replays to the same characters, to the
last digit, after the recording and the config's folder have moved."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tabletop.app import build_live
from tabletop.config import load_config
from tabletop.session import frame_to_dict
from tabletop.swap import LOCK_SUFFIX
from tests.touch_pose.conftest import models  # noqa: F401  (the learned models, once)

ROOT = Path(__file__).resolve().parents[2]


PEER_KINDS = {"osc", "serial"}   # inputs that only move when another machine sends


def shipped_configs() -> list:
    """Every shipped installation config; one that makes no characters (a tracker machine) or
    that waits on another machine's input (a stage) is listed as skipped, with why."""
    # (each file read once, with libyaml's parser where PyYAML has it: every test worker lists
    # them while collecting, 0.25 CPU s each with the pure-Python parser, twice over)
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    found = [(ROOT / "config.yaml", yaml.load((ROOT / "config.yaml").read_text(), loader))]
    for p in sorted((ROOT / "examples").rglob("*.yaml")):
        data = yaml.load(p.read_text(), loader)
        if isinstance(data, dict) and "sources" in data:
            found.append((p, data))
    out = []
    for p, data in found:
        kinds = {s.get("kind") for s in data.get("sources") or []}
        if not data.get("engines"):
            out.append(pytest.param(p, marks=pytest.mark.skip(reason="no engines: no characters")))
        elif kinds and kinds <= PEER_KINDS:
            out.append(pytest.param(p, marks=pytest.mark.skip(
                reason="its inputs come from another machine (tests/network/test_split.py runs the "
                       "pair)")))
        else:
            out.append(p)
    return out


def copy_installation(config: Path, folder: Path) -> Path:
    """The config and every file it refers to, copied under ``folder`` (same relative layout)."""
    cfg = load_config(config)
    folder.mkdir(parents=True)
    target = folder / config.name
    shutil.copy(config, target)
    for ref in cfg.refs:
        if ref.embed and ref.resolved.exists():
            dest = folder / ref.value
            dest.parent.mkdir(parents=True, exist_ok=True)
            if ref.resolved.is_dir():
                shutil.copytree(ref.resolved, dest, dirs_exist_ok=True)
            else:
                shutil.copy(ref.resolved, dest)
    return target


def frames(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines()[1:]]


def pose_counts(characters, poses: dict[str, set]) -> dict[str, int]:
    """Adds each character's pose (x, y, heading, points) to its set in ``poses``; returns how
    many different poses each has had."""
    for c in characters:
        poses.setdefault(c["name"], set()).add(
            (c["x"], c["y"], c["heading"], json.dumps(c.get("points"))))
    return {k: len(s) for k, s in poses.items()}


def run_until_moved(loop, min_ticks: int, poses: int, cap_s: float) -> None:
    """Run ``loop`` live until it has made ``min_ticks`` ticks and a character has had more
    than ``poses`` different poses (a busy machine ticks less, so it takes longer). ``cap_s``
    seconds only end a loop that hangs: mop.yaml's 240 ticks took 45 s of a test given a
    sixth of the machine (153 ticks in the 30 s cap it had; 199 at load 14-16 on 2 cores)."""
    seen: dict[str, set] = {}
    ticks = 0

    def watch(frame) -> None:
        nonlocal ticks
        ticks += 1
        counts = pose_counts(frame_to_dict(frame)["characters"], seen)   # as recorded
        if ticks >= min_ticks and max(counts.values(), default=0) > poses:
            loop.stop.set()
    loop.hooks.append(watch)
    loop.run(seconds=cap_s)


@pytest.mark.parametrize("config", shipped_configs(), ids=lambda p: p.name)
def test_replay_reproduces_the_live_characters_after_moving(tmp_path, config):
    installed = copy_installation(config, tmp_path / "repo")
    live = tmp_path / "live.jsonl"
    cfg = load_config(installed)
    # At least 1 s of ticks (4 s for mop.yaml) and until a character has had 10 poses. Every
    # discrete state a character of config.yaml, reactors.yaml or touch_pose.yaml shows in
    # 300 live ticks (its kind, validity, behaviour and action; only the numbers move) is
    # there by tick 5, 10 poses by tick 11-13: a longer run adds time, not states. mop.yaml's
    # characters take up their actions one by one (valid at ticks 26, 30, 100, 214 live):
    # its 4 s cover them. A replay fed inputs 1e-9 m off, or an engine reading the wall
    # clock, fails every config within these runs.
    seconds = 4.0 if "mop" in config.name else 1.0
    loop = build_live(cfg, headless=True, record_path=live).loop
    min_ticks = int(round(seconds / loop.period))    # what the loop makes in that time
    run_until_moved(loop, min_ticks, poses=10, cap_s=300.0)

    # Move everything: the recording to another folder, the installation away.
    moved = tmp_path / "elsewhere" / "moved.jsonl"
    moved.parent.mkdir()
    live.rename(moved)
    (tmp_path / "repo").rename(tmp_path / "gone")
    replayed = tmp_path / "replayed.jsonl"
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    r = subprocess.run([sys.executable, "-m", "tabletop", "replay", str(moved), "--fast",
                        "--no-view", "--out", str(replayed)], capture_output=True, text=True,
                       cwd=moved.parent, env=env, timeout=180)
    assert r.returncode == 0, r.stderr
    header = json.loads(moved.read_text().splitlines()[0])
    assert str(tmp_path / "repo") not in json.dumps([header["config"], list(header["files"])])

    a, b = frames(moved), frames(replayed)
    assert len(a) == len(b) and len(a) >= min_ticks   # enough ticks to compare
    differing = [fa["seq"] for fa, fb in zip(a, b) if fa["characters"] != fb["characters"]]
    assert differing == []
    assert [f["t"] for f in a] == [f["t"] for f in b]
    # The characters did something worth comparing: one at least moved, and was driven.
    poses: dict[str, set] = {}
    counts = [pose_counts(f["characters"], poses) for f in a][-1]
    assert max(counts.values()) > 10, counts
    assert any(c["valid"] for f in a for c in f["characters"])


class Operator:
    """A sink pressing designer keys at given ticks, as the view does for a person."""

    name = "operator"

    def __init__(self, commands, presses: dict[int, str]) -> None:
        self.commands, self.presses, self.ticks = commands, presses, 0

    def consume(self, frame) -> None:
        self.ticks += 1
        if self.ticks in self.presses:
            self.commands.put(self.presses[self.ticks])

    def close(self) -> None:
        pass


def replay_cli(session: Path, out: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    return subprocess.run([sys.executable, "-m", "tabletop", "replay", str(session), "--fast",
                           "--no-view", "--out", str(out)], capture_output=True, text=True,
                          cwd=session.parent, env=env, timeout=180)


def test_a_designer_session_replays_exactly(tmp_path):
    """Record a take at the table through the studio (keys), train it in the worker, try it,
    keep it: the replay runs the studio again and makes the same characters and labels."""
    from tabletop.config import validate_config
    from tabletop.kiosk.runner import Runner

    data = {
        "sources": [{"kind": "scripted", "pucks": [1, 2, 3], "seed": 2}],
        "engines": [{"kind": "puppet_master", "name": "lover",
                     "behavior": str(ROOT / "behaviors" / "library" / "lover"),
                     "main": {"puck": 3},
                     "designer": {"enabled": True, "main_puck": 1, "react_puck": 2,
                                  "min_seconds": 1.0}}],
        "studio": {"countdown_s": 0.5, "review": False},
        "view": {"enabled": False}}
    cfg = validate_config(data, str(tmp_path / "designer.yaml"), tmp_path)
    live = tmp_path / "live.jsonl"
    runner = Runner(tmp_path / "designer.yaml", cfg, headless=True, record_path=live)
    inst = runner._build(cfg)
    inst.loop.sinks.insert(0, Operator(inst.loop.commands, {
        10: "designer.record", 160: "designer.record", 215: "designer.keep"}))
    inst.loop.run(max_ticks=240)   # by ticks: a loaded machine skips late ticks' slots
    assert (tmp_path / "library" / "lover" / "demonstration.csv").is_file()  # kept live

    out = tmp_path / "replayed.jsonl"
    r = replay_cli(live, out)
    assert r.returncode == 0, r.stderr
    a, b = frames(live), frames(out)
    assert len(a) == len(b) > 200
    states = [c.get("action") for f in a for c in f["characters"] if c["name"] == "studio"]
    assert {"countdown", "recording", "training", "trying"} <= set(states)
    labels = [c.get("label", "") for f in a for c in f["characters"]]
    assert any("kept as lover" in s for s in labels)
    assert any(f.get("consumed", {}).get("studio") for f in a)   # the studio's inputs recorded

    def same(x: dict, y: dict) -> bool:
        return x["characters"] == y["characters"]
    assert [fa["seq"] for fa, fb in zip(a, b) if not same(fa, fb)] == []
    # What the replay kept went into its own folder, not the installation's library.
    assert sorted(p.name for p in (tmp_path / "library").iterdir()
                  if not p.name.endswith(LOCK_SUFFIX)) == ["lover"]

    # Without the studio's inputs (a recording of what the engines saw only) the replay makes
    # no take: the characters differ from the stop on.
    stripped = tmp_path / "stripped.jsonl"
    lines = live.read_text().splitlines()
    stripped.write_text("\n".join([lines[0]] + [json.dumps(
        {k: v for k, v in json.loads(x).items() if k != "consumed"}) for x in lines[1:]]) + "\n")
    # (replayed here, not in a process: a state this process kept from the live run could
    # only make the characters alike, failing the test, never differ)
    from tabletop.cli import main as cli
    assert cli(["replay", str(stripped), "--fast", "--no-view", "--out",
                str(tmp_path / "stripped_out.jsonl")]) == 0
    c = frames(tmp_path / "stripped_out.jsonl")
    assert sum(not same(fa, fc) for fa, fc in zip(a, c)) > 100


def rotated_config(tmp_path: Path):
    """A scripted table with one reactor, recording into ``s/`` in parts of 0.17 MB (the
    header alone is 150 kB: a new part every few dozen frames)."""
    from tabletop.config import validate_config
    return validate_config({
        "sources": [{"kind": "scripted", "pucks": [1, 2], "seed": 3}],
        "engines": [{"kind": "puppet_master", "name": "lover",
                     "behavior": str(ROOT / "behaviors" / "library" / "lover")}],
        "view": {"enabled": False},
        "recorder": {"enabled": True, "folder": "s", "max_mb": 0.17}},
        str(tmp_path / "k.yaml"), tmp_path)


def test_the_parts_of_a_rotated_session_replay_exactly_in_order(tmp_path, capfd):
    cfg = rotated_config(tmp_path)
    inst = build_live(cfg)
    inst.loop.run(max_ticks=150)
    parts = inst.recorder.paths
    assert len(parts) >= 3
    out = tmp_path / "replayed.jsonl"
    env = dict(os.environ, SDL_VIDEODRIVER="dummy")
    args = [sys.executable, "-m", "tabletop", "replay", "--fast", "--no-view", "--out", str(out)]
    r = subprocess.run(args + [str(p) for p in parts], capture_output=True, text=True, env=env,
                       cwd=tmp_path, timeout=180)
    assert r.returncode == 0, r.stderr
    live = [f for p in parts for f in frames(p)]
    again = frames(out)
    assert len(live) == len(again)
    assert [f["characters"] for f in live] == [f["characters"] for f in again]
    # Out of order, they are refused with one line naming the file and line (the refusal
    # read here: the command line's in this process).
    capfd.readouterr()
    assert refused(["--out", str(tmp_path / "again.jsonl"), str(parts[1]), str(parts[0])]) == 2
    err = capfd.readouterr().err
    assert "part 1 cannot follow part 2" in err
    assert str(parts[0]) in err and len(err.strip().splitlines()) == 1, err


def refused(args: list[str]) -> int:
    """``tabletop replay --fast --no-view ARGS`` in this process (a refusal: nothing plays)."""
    from tabletop.cli import main as cli
    return cli(["replay", "--fast", "--no-view", *args])


def test_a_part_of_another_session_is_refused_before_anything_plays(tmp_path, capfd):
    """Two sessions of one config in one folder (a kiosk's, before and after a restart), each
    in parts: the first session's part 1 followed by the second's part 2 is refused in one line
    naming both sessions, before a frame is written to --out (it was replayed on as if the
    first session went on: same config, later times)."""
    cfg = rotated_config(tmp_path)
    sessions = []
    for _ in range(2):
        inst = build_live(cfg)
        inst.loop.run(max_ticks=80)
        sessions.append(inst.recorder.paths)
    assert all(len(parts) >= 2 for parts in sessions)
    ids = [json.loads(parts[0].read_text().split("\n", 1)[0])["session"] for parts in sessions]
    assert ids[0] != ids[1]
    out = tmp_path / "mixed.jsonl"
    capfd.readouterr()
    assert refused(["--out", str(out), str(sessions[0][0]), str(sessions[1][1])]) == 2
    err = capfd.readouterr().err
    assert err.strip() == (
        f"tabletop replay: error: {sessions[1][1]}: line 1: a part of session {ids[1]}, not of "
        f"{sessions[0][0]}'s session {ids[0]}; give the parts of one session"), err
    assert not out.exists()
    # another session's part 1 is of another session too ("part 1 cannot follow part 1")
    assert refused([str(sessions[0][0]), str(sessions[1][0])]) == 2
    err = capfd.readouterr().err
    assert f"a part of session {ids[1]}, not of" in err, err


def test_a_touch_pose_designer_session_replays_exactly(tmp_path, models):
    """A touch-pose action posed, trained, tried and kept through the studio (physics on):
    ``tabletop replay`` makes the same characters, the designed action's try included."""
    from tabletop.cli import main as cli
    from tabletop.config import validate_config
    from tabletop.kiosk.runner import Runner
    from tabletop.kiosk.simulate import SimClock
    from tests.studio.test_studio_touch_pose import DRAG_S, Finger, arc, part_at

    cfg = validate_config({
        "loop": {"rate_hz": 30}, "sources": [{"kind": "scripted", "pucks": []}],
        "engines": [{"kind": "touch_pose", "name": "poser", "view": [90, 15], "mouse": False}],
        "studio": {"countdown_s": 0.5, "review": False}, "view": {"enabled": False}},
        str(tmp_path / "c.yaml"), tmp_path)
    clock = SimClock()
    live = tmp_path / "live.jsonl"
    runner = Runner(tmp_path / "c.yaml", cfg, headless=True, record_path=live, clock=clock)
    inst = runner._build(cfg)
    engine, t0, starts = inst.engines[0], clock(), {}

    def where(t):
        for phase, a in (("take", 1.0), ("try", 3.5)):
            if a <= t - t0 <= a + DRAG_S:
                starts.setdefault(phase, part_at(engine, "right_hand"))
                return starts[phase] + arc((t - t0 - a) / DRAG_S)
        return None

    inst.loop.inputs.sources.append(Finger(clock, where))
    inst.loop.sinks.insert(0, Operator(inst.loop.commands, {
        5: "designer.record", 70: "designer.record", 170: "designer.keep"}))
    inst.loop.inputs.open()
    for _ in range(180):
        inst.loop.tick()
        clock.advance(1 / 30)
    inst.loop.close()
    out = tmp_path / "replayed.jsonl"
    assert cli(["replay", str(live), "--fast", "--no-view", "--out", str(out)]) == 0
    a, b = frames(live), frames(out)
    played = [c.get("action") for f in a for c in f["characters"] if c["name"] == "poser"]
    assert "poser-action" in played                               # the try played it
    assert (tmp_path / "pose_actions" / "poser-action" / "action.json").is_file()
    assert len(a) == len(b) == 180
    assert [fa["seq"] for fa, fb in zip(a, b) if fa["characters"] != fb["characters"]] == []
