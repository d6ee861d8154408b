"""A soak: half an hour of table time on a simulated clock (synthetic camera, every engine,
studio and kiosk on, a studio take every five minutes): memory and the live Python objects
stay flat and nothing fails. The rate staying steady, and the hour, are measured by
bench/soak.py."""

from pathlib import Path

import yaml

from tabletop.kiosk.simulate import soak, soak_config

ROOT = Path(__file__).resolve().parents[2]


def test_half_a_simulated_hour_keeps_memory_flat(tmp_path):
    """Measured over the 1,200 ticks after the ten-minute warm-up: +1.2 MB and -2 objects
    (within +-100); scripted pucks keeping every segment since the start (tracking.visitor
    without ``forget``) grew 596 objects. The limits are the simulated hour's (10 MB, 500
    objects over 3,000 ticks) for the ticks measured here: the same growth per tick fails."""
    path = tmp_path / "config.yaml"
    # review sheets (matplotlib, ~0.5 s each) are left to bench/soak.py
    path.write_text(yaml.safe_dump(soak_config(ROOT, rate_hz=1.0, review=False)))
    # sampled every 150 s: 12 full collections, 1.1-1.2 CPU s of the test with every test
    # module loaded; every 600 s (3) 0.3 s, but the test's CPU 14.3-15.3 -> 15.5-16.5 s and
    # the growth measured 0.73-0.81 -> 1.23-1.24 MB (three runs each): kept at 150
    r = soak(path, seconds=1800, rate_hz=1.0, warmup_s=600, every_s=150,
             studio_keys_every_s=300)
    assert r["ticks"] == 1800 and r["errors"] == 0
    assert r["tries"] == 6                           # every take recorded, trained, discarded
    growth = r["rss_end_bytes"] - r["rss_start_bytes"]
    assert growth < 4e6, [round(x / 1e6, 1) for x in r["rss_samples"]]
    # nothing piles up either: the live Python objects stay level after the warm-up
    assert r["objects_end"] - r["objects_start"] < 200, r["objects_samples"]
    status = (tmp_path / "status.json").read_text()
    assert '"mode":"live"' in status or '"mode":"attract"' in status
