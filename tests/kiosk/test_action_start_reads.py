"""A kiosk's MOP actions followed on disk hold the bytes each playing action was built from:
read at the start once per file, however many actions name it."""

import shutil

from tabletop.config import validate_config
from tabletop.kiosk import actions
from tabletop.kiosk.actions import ActionReloader
from tabletop.plugins import mop
from tabletop.plugins.mop_table import EXAMPLES
from tabletop.registry import BuildContext
from tests.reads import counting_reads

GESTURES = EXAMPLES / "mop" / "gestures"


def test_each_followed_file_is_read_once_at_the_start(tmp_path, monkeypatch):
    for name in ("circle", "line"):
        shutil.copy(GESTURES / f"{name}.csv", tmp_path / f"{name}.csv")
    engine = {"kind": "mop", "name": "mop",
              "performers": [{"name": "hand", "inputs": [{"kind": "puck", "id": 1}]}],
              "characters": [
                  {"name": "walker", "kind": "creature", "performer": "hand", "actions": [
                      {"name": "circle", "template": "circle.csv", "motion": "walk"},
                      {"name": "line", "template": "line.csv", "motion": "curl"}]},
                  {"name": "lone", "kind": "creature", "performer": "hand", "actions": [
                      {"name": "circle", "template": "circle.csv", "motion": "strike"}]}]}
    cfg = validate_config({"sources": [{"kind": "scripted"}], "engines": [engine]},
                          str(tmp_path / "config.yaml"), tmp_path)
    ctx = BuildContext((1.2, 0.8), 60.0, cfg, tmp_path)
    ctx.shared["kiosk_start"] = True
    stage = mop.build(cfg["engines"][0], ctx)
    reads = counting_reads(monkeypatch, actions, "read_regular_bytes")
    reloader = ActionReloader(stage, every_s=0.0)
    assert reads == {"circle.csv": 1, "line.csv": 1}
    circle = (GESTURES / "circle.csv").read_bytes()
    held = {(m["character"]["name"], m["action"]["name"]): m["data"] for m in reloader.watched}
    assert held == {("walker", "circle"): [circle], ("lone", "circle"): [circle],
                    ("walker", "line"): [(GESTURES / "line.csv").read_bytes()]}
