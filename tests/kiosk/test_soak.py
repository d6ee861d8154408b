"""A soak: twelve and a half minutes of table time on a simulated clock (synthetic camera,
every engine, studio and kiosk on, a studio take every 200 s): memory and the live Python
objects stay flat and nothing fails. The long forms are bench/soak.py's (`python -m bench
--soaks`): the hour with the scripts' whole history (tracking.visitor.HISTORY_S), the rate
staying steady."""

from pathlib import Path

import yaml

from tabletop.kiosk.simulate import soak_config
from tests.children import python_json

ROOT = Path(__file__).resolve().parents[2]

# The soak runs in a process of its own, as a kiosk does: its resident memory is then the
# installation's alone, not a test worker's after the tests it ran before (in a worker that had
# run the other kiosk and tabletop tests the same code grew 1.4-4.2 MB over the ticks measured;
# alone, 0.13-0.25 MB).
SOAK = """
import json, sys
from pathlib import Path
from tabletop.kiosk.simulate import soak
from tracking import visitor
visitor.HISTORY_S = 60.0
visitor._FORGET_AT = 1
r = soak(Path(sys.argv[1]), seconds=750, rate_hz=1.0, warmup_s=450, every_s=150,
         studio_keys_every_s=200)
print(json.dumps(r))
"""


def test_twelve_simulated_minutes_keep_memory_flat(tmp_path):
    """Measured over the 300 ticks after a 7.5-minute warm-up: +0.13-0.25 MB and -22 to -38
    objects (two runs); scripted pucks keeping every segment since the start
    (tracking.visitor without ``forget``) grew 205 objects. The limits are the simulated
    hour's (10 MB, 500 objects over 3,000 ticks) for the ticks measured here: the same growth
    per tick fails."""
    # the scripts remember 60 s instead of 600 s (read at each pose) and drop each stale entry
    # at once, not 64 together: their history is full early in the warm-up (objects level
    # from 150 s) and its sawtooth is 40 objects, not 85 (samples every 30 s after 150 s:
    # 62-97 against 65-149 dropping 64 together), so 750 ticks tell what 1,200 did (CPU
    # 19.6 -> 14-15 s). The resident memory still settles for longer (+1.2, +0.5, +0.2,
    # +0.1 MB in the 150 s periods from 150 s): measured from 450 s. The whole history's soak
    # is bench/soak.py's
    # (SOAK sets them in its process)
    path = tmp_path / "config.yaml"
    # review sheets (matplotlib, ~0.5 s each) are left to bench/soak.py
    path.write_text(yaml.safe_dump(soak_config(ROOT, rate_hz=1.0, review=False)))
    # sampled every 150 s: every 600 s the growth measured 0.73-0.81 -> 1.23-1.24 MB over the
    # half hour (three runs each)
    r = python_json(SOAK, str(path), timeout=600)
    assert r["ticks"] == 750 and r["errors"] == 0
    assert r["tries"] == 4                           # every take recorded, trained, discarded
    growth = r["rss_end_bytes"] - r["rss_start_bytes"]
    assert growth < 1e6, [round(x / 1e6, 1) for x in r["rss_samples"]]
    # nothing piles up either: the live Python objects stay level after the warm-up
    assert r["objects_end"] - r["objects_start"] < 50, r["objects_samples"]
    status = (tmp_path / "status.json").read_text()
    assert '"mode":"live"' in status or '"mode":"attract"' in status
