"""A kiosk started (a reboot, a restart by its supervisor) while its recordings folder cannot be
written: the last good config names the same folder, so a refused start would restart the kiosk
for ever. It runs without recording, the status says why, and once the folder takes files again
the recording starts. Outside a kiosk the same start is refused, naming the key."""

from pathlib import Path

import pytest
import yaml

from tabletop.config import load_config
from tabletop.kiosk.runner import Runner
from tabletop.kiosk.simulate import SimClock, simulated
from tabletop.recorder_resume import RESUME_EVERY_S
from tabletop.schema import ConfigError
from tests.kiosk.test_kiosk_lock import status
from tracking.scenes import wait_for


def _config(tmp_path: Path) -> Path:
    """A kiosk recording into ``blocked/sessions``, where ``blocked`` is a file: the folder can
    be neither made nor written (as a drive unmounted or remounted read-only leaves it; the
    tests run as root, for whom permission bits refuse nothing)."""
    (tmp_path / "blocked").write_text("not a folder")
    cfg_path = tmp_path / "config.yaml"
    cfg_path.write_text(yaml.safe_dump({
        "loop": {"rate_hz": 30},
        "sources": [{"kind": "scripted", "name": "visitor", "pucks": [1]}],
        "view": {"size": [320, 180], "headless": True},
        "recorder": {"enabled": True, "folder": "blocked/sessions"},
        "kiosk": {"heartbeat": {"enabled": False}, "status_file": "status.json"},
    }))
    return cfg_path


def test_a_kiosk_starts_without_recording_into_an_unwritable_folder_and_resumes(tmp_path):
    cfg_path = _config(tmp_path)
    clock = SimClock()
    runner, inst = simulated(load_config(cfg_path), cfg_path, clock, kiosk=True, studio=False)
    (recorder,) = [s for s in inst.loop.sinks if s.name == "recorder"]
    assert recorder.failed is not None and recorder.failed.startswith(str(tmp_path / "blocked"))

    def run(seconds: float) -> None:
        for _ in range(int(seconds * 30)):
            inst.loop.tick()
            clock.advance(1 / 30)
    try:
        run(5.0)
        assert wait_for(lambda: (status(tmp_path).get("recording") or {}).get("failed"),
                        20.0)
        (tmp_path / "blocked").unlink()               # the folder can be made again
        run(RESUME_EVERY_S + 5.0)
        assert recorder.failed is None and recorder.frames > 0
    finally:
        inst.loop.close()
    parts = sorted((tmp_path / "blocked" / "sessions").iterdir())
    assert parts and recorder.gaps and recorder.gaps[0].startswith(str(tmp_path / "blocked"))


def test_outside_a_kiosk_an_unwritable_recording_folder_stops_the_start(tmp_path):
    cfg_path = _config(tmp_path)
    runner = Runner(cfg_path, load_config(cfg_path), headless=True, kiosk=False, strict=True)
    with pytest.raises(ConfigError, match=r"recorder\.folder: .*cannot start a recording there"):
        runner._build(runner.cfg)
