"""A studio session in which a library file is fixed on disk mid-run (a MOP character's
actions.yaml, a touch-pose action): the studio follows it from the next frame, and
``tabletop replay`` follows it from the same frame, the characters alike to the last digit."""

import re
import shutil
from pathlib import Path

import yaml

from tabletop.cli import main as cli
from tabletop.config import validate_config
from tabletop.kiosk.runner import Runner
from tabletop.kiosk.simulate import SimClock
from tests.tabletop.test_replay_exact import frames
from tests.touch_pose.conftest import models  # noqa: F401  (the learned models, once)

GESTURES = Path(__file__).resolve().parents[2] / "examples" / "mop" / "gestures"
RATE = 30


def _run(tmp_path: Path, data: dict, fix_at: int, fix, ticks: int) -> tuple[Path, Runner]:
    """``data`` run as a studio by hand at ``RATE`` Hz, recorded, its studio's libraries looked
    at every tick; ``fix(runner)`` called after tick ``fix_at``. Returns the recording, the
    runner."""
    cfg = validate_config(data, str(tmp_path / "c.yaml"), tmp_path)
    clock = SimClock()
    live = tmp_path / "live.jsonl"
    runner = Runner(tmp_path / "c.yaml", cfg, headless=True, record_path=live, clock=clock)
    inst = runner._build(cfg)
    for t in runner.studio.targets.values():
        t._poller.every_s = 0.0
    inst.loop.inputs.open()
    for k in range(ticks):
        inst.loop.tick()
        clock.advance(1 / RATE)
        if k == fix_at:
            fix(runner)
    inst.loop.close()
    return live, runner


def _replayed(tmp_path: Path, live: Path) -> tuple[list, list]:
    """The live frames and the replay's, the folders the bad files' paths name (the studio's
    status line: the installation's, the replay's copy) left out."""
    out = tmp_path / "replayed.jsonl"
    assert cli(["replay", str(live), "--fast", "--no-view", "--out", str(out)]) == 0
    return _unplaced(frames(live)), _unplaced(frames(out))


def _unplaced(recorded: list) -> list:
    for f in recorded:
        for c in f["characters"]:
            if "label" in c:
                c["label"] = re.sub(r"/\S*/(lib|pose_actions)/", r"\1/", c["label"])
    return recorded


def test_a_mop_library_file_fixed_mid_run_is_followed_by_the_replay(tmp_path):
    lib = tmp_path / "lib" / "lizard"
    lib.mkdir(parents=True)
    shutil.copy(GESTURES / "line.csv", lib / "line.csv")
    shutil.copy(GESTURES / "line.csv", tmp_path / "drawn.csv")
    good = yaml.safe_dump({"actions": [{"name": "line", "template": "line.csv",
                                        "motion": "curl"}]})
    (lib / "actions.yaml").write_text("actions: [oops\n")
    data = {"loop": {"rate_hz": RATE},
            "sources": [{"kind": "scripted", "pucks": [], "performers": [
                {"puck": 1, "home": [0.5, 0.4], "gestures": ["drawn.csv"],
                 "speed": [1.0, 1.0]}]}],
            "engines": [{"kind": "mop", "name": "mop", "library": "lib",
                         "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
                         "characters": [{"name": "lizard", "kind": "creature",
                                         "performer": "hand", "motions": ["strike", "curl"]}]}],
            "studio": {"enabled": True, "countdown_s": 0.5, "review": False},
            "view": {"enabled": False}}
    live, runner = _run(tmp_path, data, 20, lambda _: (lib / "actions.yaml").write_text(good), 300)
    a, b = _replayed(tmp_path, live)
    played = [c.get("action") for f in a for c in f["characters"] if c["name"] == "lizard"]
    assert "line" in played                                  # followed live once fixed
    assert "line" not in played[:23]
    assert len(a) == len(b) == 300
    assert [fa["seq"] for fa, fb in zip(a, b) if fa["characters"] != fb["characters"]] == []


def test_a_touch_pose_action_fixed_mid_run_is_followed_by_the_replay(tmp_path, models):
    """The studio's status line stops naming the bad file from the frame after the fix, live
    and in the replay (which knows the action from that frame: its library rewritten)."""
    import numpy as np

    from behaviors.touch_pose.designed import to_json
    from behaviors.touch_pose.humanoid import Pose
    bad = tmp_path / "pose_actions" / "greet" / "action.json"
    bad.parent.mkdir(parents=True)
    bad.write_text('{\n  "format": "tabletop.pose_action",\n  "part": ')
    data = {"loop": {"rate_hz": RATE}, "sources": [{"kind": "scripted", "pucks": []}],
            "engines": [{"kind": "touch_pose", "name": "poser", "physics": False,
                         "mouse": False}],
            "studio": {"enabled": True, "countdown_s": 0.5, "review": False},
            "view": {"enabled": False}}

    def fix(runner) -> None:
        core = runner.studio.targets["poser"].core
        rots = np.tile([1.0, 0.0, 0.0, 0.0], (len(core.body.names), 1))
        poses = [Pose(np.array([0.3 * k / 40, 0.0, 0.9]), rots) for k in range(40)]
        bad.write_text(to_json("greet", "pelvis", np.linspace(0.0, 2.0, 40), poses))

    live, runner = _run(tmp_path, data, 10, fix, 40)
    assert "greet" in {a.name for a in runner.studio.targets["poser"].core.m.actions}
    a, b = _replayed(tmp_path, live)
    said = ["bad library file" in c.get("label", "") for f in a for c in f["characters"]
            if c["name"] == "studio"]
    assert said[:12] == [True] * 12 and not any(said[12:])
    assert len(a) == len(b) == 40
    assert [fa["seq"] for fa, fb in zip(a, b) if fa["characters"] != fb["characters"]] == []


def test_a_replay_never_writes_a_recorded_library_outside_its_own_folder(tmp_path, caplog):
    """A library the recording could not carry (too large) is read where the installation
    has it: the replay's recorded reload of it is said and skipped, the folder left as it is."""
    import base64

    from tabletop.frames import Frame
    from tabletop.plugins.mop_table import build, designer_config
    from tabletop.studio.mop_table import StudioTable
    from tabletop.studio.reloader import RecordedLibraries
    engine = build(designer_config(tmp_path), tmp_path)
    table = StudioTable(engine, tmp_path / "lib", focus="mop/lizard")
    (tmp_path / "lib" / "lizard").mkdir(parents=True)
    (tmp_path / "lib" / "lizard" / "actions.yaml").write_text("actions: []\n")
    (tmp_path / "replay").mkdir()
    files = {"actions.yaml": base64.b64encode(b"actions: [oops\n").decode("ascii")}
    frame = Frame(0, 0.0, consumed={"reload": {"libraries": {"mop/lizard": files}}})
    assert RecordedLibraries(table.studio, tmp_path / "replay")(frame) is frame
    assert (tmp_path / "lib" / "lizard" / "actions.yaml").read_text() == "actions: []\n"
    assert any("not among the recording's files" in r.getMessage() for r in caplog.records)
    RecordedLibraries(table.studio, tmp_path)(frame)           # under the replay's folder
    assert (tmp_path / "lib" / "lizard" / "actions.yaml").read_text() == "actions: [oops\n"
    assert table.studio.problems and "actions.yaml" in table.studio.problems[0]
