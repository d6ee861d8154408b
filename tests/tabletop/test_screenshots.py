"""A snapshot of the default installation, made as ``make screenshots`` makes the README's:
characters and pucks are in it, not an empty table."""

from pathlib import Path

import numpy as np
import pygame

from tabletop import screenshots
from tabletop.config import load_config
from tabletop.screenshots import ROOT, shoot


def test_default_config_snapshot_shows_characters_and_pucks(tmp_path, monkeypatch):
    def load(path):   # a 720p camera frame late on a busy machine leaves the pucks seen
        cfg = load_config(path)        # (their cold ring drawn), not coasting
        cfg["tracking"] = dict(cfg["tracking"], stale_s=2.0)
        return cfg
    monkeypatch.setattr(screenshots, "load_config", load)
    out = shoot(ROOT / "config.yaml", 6.0, tmp_path / "default.png", overlay=False)
    img = pygame.surfarray.array3d(pygame.image.load(str(out))).astype(int)
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    character = (r > 200) & (g < 170) & (b > 110) & (r > b + 40)   # the pink "lover"
    halo = (b > 150) & (g > 150) & (b > r + 20)                      # a seen puck's cold ring
    assert np.count_nonzero(character) > 300
    assert np.count_nonzero(halo) > 150
    assert Path(out).stat().st_size > 10_000


def test_make_screenshots_refuses_bad_arguments_in_one_line_before_running(tmp_path, capfd,
                                                                           monkeypatch):
    """``--seconds nan`` ran for ever and then wrote into docs/; a negative time ran and said
    "no snapshot was written"; an --out that cannot be a folder was a traceback after the runs.
    (The command's main in this process, as ``python -m tabletop.screenshots`` runs it: four
    interpreters' starts fewer; nothing runs: ``shoot`` fails the test if called.)"""
    def ran(*_):
        raise AssertionError("ran before refusing")
    monkeypatch.setattr(screenshots, "shoot", ran)
    (tmp_path / "file").write_text("x")
    shots = str(tmp_path / "shots")
    cases = [(["--seconds", "-1", "--out", shots], 2,
              "--seconds '-1' must be a positive number of seconds"),
             (["--seconds", "nan", "--out", shots], 2,
              "--seconds 'nan' must be a positive number of seconds"),
             (["--out", str(tmp_path / "file")], 2, "is a file; give the folder"),
             (["--out", "/proc/no/such"], 1, "screenshots: error: /proc/no/such: ")]
    for args, status, said in cases:
        try:
            code = screenshots.main(["--only", "default", *args])
        except SystemExit as stop:      # argparse's refusals
            code = stop.code
        out, err = capfd.readouterr()
        assert code == status and said in err, (args, err[-300:])
        assert "Traceback" not in err and not out.strip()
