"""A soak: twenty minutes of table time on a simulated clock (synthetic camera, every engine,
studio and kiosk on, a studio take every 200 s): memory and the live Python objects stay flat
and nothing fails. The rate staying steady, and the hour with the scripts' whole history
(tracking.visitor.HISTORY_S), are measured by bench/soak.py."""

from pathlib import Path

import yaml

from tabletop.kiosk.simulate import soak, soak_config
from tracking import visitor

ROOT = Path(__file__).resolve().parents[2]


def test_twenty_simulated_minutes_keep_memory_flat(tmp_path, monkeypatch):
    """Measured over the 900 ticks after the five-minute warm-up: +0.6 MB and +7 objects;
    scripted pucks keeping every segment since the start (tracking.visitor without
    ``forget``) grew 485 objects. The limits are the simulated hour's (10 MB, 500 objects over
    3,000 ticks) for the ticks measured here: the same growth per tick fails."""
    # the scripts remember 150 s instead of 600 s (read at each pose): their history is full
    # within the warm-up (objects level from 300 s, not 1,000 s), so 1,200 ticks tell what
    # 1,800 did (CPU 27 -> 18 s); the whole history's soak is bench/soak.py's
    monkeypatch.setattr(visitor, "HISTORY_S", 150.0)
    path = tmp_path / "config.yaml"
    # review sheets (matplotlib, ~0.5 s each) are left to bench/soak.py
    path.write_text(yaml.safe_dump(soak_config(ROOT, rate_hz=1.0, review=False)))
    # sampled every 150 s: 8 full collections (12 were 1.1-1.2 CPU s of the test with every
    # test module loaded); every 600 s the growth measured 0.73-0.81 -> 1.23-1.24 MB over the
    # half hour (three runs each): kept at 150
    r = soak(path, seconds=1200, rate_hz=1.0, warmup_s=300, every_s=150,
             studio_keys_every_s=200)
    assert r["ticks"] == 1200 and r["errors"] == 0
    assert r["tries"] == 6                           # every take recorded, trained, discarded
    growth = r["rss_end_bytes"] - r["rss_start_bytes"]
    assert growth < 3e6, [round(x / 1e6, 1) for x in r["rss_samples"]]
    # nothing piles up either: the live Python objects stay level after the warm-up
    assert r["objects_end"] - r["objects_start"] < 150, r["objects_samples"]
    status = (tmp_path / "status.json").read_text()
    assert '"mode":"live"' in status or '"mode":"attract"' in status
