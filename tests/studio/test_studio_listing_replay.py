"""A studio session in which a behaviour folder is added to the Puppet Master library on disk
mid-run (another studio on the same library keeps a take): the shelf lists it, ] picks it, and
``tabletop replay`` picks the same behaviour from the same frame, the characters alike to the
last digit (the listing's files are recorded as the other library reloads are)."""

import json
import shutil
from pathlib import Path

from tabletop.config import validate_config
from tabletop.kiosk.runner import Runner
from tabletop.kiosk.simulate import SimClock
from tests.studio.test_studio_library_replay import _replayed

SHIPPED = Path(__file__).resolve().parents[2] / "behaviors" / "library"
RATE = 30


def test_a_behaviour_added_to_the_library_mid_run_is_picked_alike_by_the_replay(tmp_path):
    lib = tmp_path / "lib"
    shutil.copytree(SHIPPED / "lover", lib / "lover")
    data = {"loop": {"rate_hz": RATE},
            "sources": [{"kind": "scripted", "pucks": [1]}],
            "engines": [{"kind": "puppet_master", "name": "pet", "main": {"puck": 1},
                         "designer": {"enabled": True, "library": "lib",
                                      "background_training": False}}],
            "studio": {"enabled": True, "countdown_s": 0.5, "review": False},
            "view": {"enabled": False}}
    cfg = validate_config(data, str(tmp_path / "c.yaml"), tmp_path)
    clock, live = SimClock(), tmp_path / "live.jsonl"
    runner = Runner(tmp_path / "c.yaml", cfg, headless=True, record_path=live, clock=clock)
    inst = runner._build(cfg)
    (target,) = runner.studio.targets.values()
    target.lib_poller.every_s = 0.0
    inst.loop.inputs.open()
    for k in range(120):
        if k == 10:                     # lover picked
            inst.loop.commands.put("designer.item_next")
        if k == 40:                     # another studio keeps a bully
            shutil.copytree(SHIPPED / "bully", lib / "bully")
        if k == 60:                     # ] goes on to it (the listing: bully, lover)
            inst.loop.commands.put("designer.item_next")
        inst.loop.tick()
        clock.advance(1 / RATE)
    inst.loop.close()
    assert inst.engines[0].behavior_name == "bully"
    # the listing records only the files that changed: bully's, not lover's (in play)
    listed = [f["consumed"]["reload"]["libraries"]["pet library"]
              for f in map(json.loads, live.read_text().splitlines())
              if "pet library" in f.get("consumed", {}).get("reload", {}).get("libraries", {})]
    bully = {str(p.relative_to(lib)) for p in (lib / "bully").rglob("*") if p.is_file()}
    assert listed and set().union(*listed) == bully, [sorted(x) for x in listed]
    assert sum(len(b) for x in listed for b in x.values()) < 1.4 * sum(
        (lib / name).stat().st_size for name in bully)
    a, b = _replayed(tmp_path, live)
    assert len(a) == len(b) == 120
    assert [fa["seq"] for fa, fb in zip(a, b) if fa["characters"] != fb["characters"]] == []


def test_a_part_header_carries_a_listing_file_by_file():
    """A listing record holds only the files that changed, so a later part's ``reloaded``
    merges each listing's records file by file (the latest of each, removals kept); a target's
    own library record replaces the one before."""
    from tabletop.parts import carried
    from tabletop.studio.reloader import REMOVED
    first = {"libraries": {"pet library": {"bully/a.csv": "YQ==", "shy/a.csv": "YQ=="},
                           "pet": {"x.csv": "YQ==", "y.csv": "YQ=="}}}
    later = {"libraries": {"pet library": {"shy/a.csv": REMOVED, "keen/a.csv": "Yg=="},
                           "pet": {"x.csv": "Yg=="}}}
    state = carried(carried({}, first), later)
    assert state["libraries"] == {
        "pet library": {"bully/a.csv": "YQ==", "shy/a.csv": REMOVED, "keen/a.csv": "Yg=="},
        "pet": {"x.csv": "Yg=="}}
