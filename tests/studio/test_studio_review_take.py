"""A try's review sheet shows the take that was tried: generated with the take's own
parameters on the table it was made on, and a path that stood still is still drawn."""

from pathlib import Path

import numpy as np
from PIL import Image

from behaviors.puppet_master import designers
from tabletop.frames import Frame
from tabletop.studio.review import review_sheet
from tests.studio.test_studio_keys import Bench, build, demo_frames

SHIPPED = Path(__file__).resolve().parents[2] / "behaviors" / "library"


def test_the_review_of_an_afraid_take_is_generated_as_it_was_tried(tmp_path):
    """A new take of the afraid character trains with its edge_percentile 50 on the 1.2 x
    0.8 m table (the character tried and kept); its review sheet was generated with the
    defaults on the take's own area, another character."""
    (e,) = build([{"kind": "puppet_master", "name": "afraid",
                   "behavior": str(SHIPPED / "afraid"), "main": {"puck": 1},
                   "designer": {"enabled": True, "library": str(tmp_path / "lib"),
                                "background_training": False}}])
    bench = Bench([e], tmp_path, review=True)
    bench.session.wait(60.0)                                  # the plotting library loaded
    demo = designers.demonstrate("afraid", seed=3, seconds=12)
    for f in demo_frames(demo, {5: ("designer.record",), 400: ("designer.record",)}):
        bench.step(f)
    target = bench.studio.target
    params = target.take_params()
    assert params["edge_percentile"] == 50.0 and params["table_width"] == 1.2
    _, studio = bench.step(Frame(seq=9000, t=900.0, commands=("designer.keep",)))
    assert "kept as afraid" in studio.label
    bench.session.wait(60.0)
    (png,) = sorted((tmp_path / "studio").glob("*-try001.png"))
    taken = np.asarray(target.demo)
    review_sheet("behaviour", taken, tmp_path / "as_tried.png", title="afraid: kept afraid",
                 params=params)
    review_sheet("behaviour", taken, tmp_path / "defaults.png", title="afraid: kept afraid")
    assert png.read_bytes() == (tmp_path / "as_tried.png").read_bytes()
    assert png.read_bytes() != (tmp_path / "defaults.png").read_bytes()


def test_a_take_that_stood_still_is_drawn(tmp_path):
    """Both pucks held still for the take: the demonstration was drawn as lines of no length,
    an empty panel. Each path's start is a dot: the reactor's orange shows beyond the legend's
    sample (17 pixels of it; the dot 37 more)."""
    demo = np.zeros((300, 7))
    demo[:, 0] = np.arange(300) / 40.0
    demo[:, 1:4] = (0.5, 0.4, 0.0)
    demo[:, 4:7] = (0.7, 0.4, 3.1)
    review_sheet("behaviour", demo, tmp_path / "still.png", title="pet: kept pet")
    a = np.asarray(Image.open(tmp_path / "still.png").convert("RGB")).astype(int)
    left = a[:, : a.shape[1] // 2]                          # the demonstration's panel
    orange = int((np.abs(left - [255, 127, 14]).sum(-1) < 60).sum())
    blue = int((np.abs(left - [31, 119, 180]).sum(-1) < 60).sum())
    assert orange > 35 and blue > 35, (orange, blue)
