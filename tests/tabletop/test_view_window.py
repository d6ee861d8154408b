"""The view drawn into a window of another size than ``view.size`` (a fullscreen window on a
display that could not switch to it gets the desktop's size)."""

import numpy as np
import pygame
import pytest

from calibration.transforms import apply_homography
from tabletop.frames import Frame, Puck
from tabletop.renderer import Renderer
from tabletop.view import scaled_homography

TABLE = (1.2, 0.8)
ASKED, GIVEN = (1280, 720), (1920, 1080)
# a keystoned table_to_projector for a 1280x720 projector (the simulated rig's, rounded)
H = np.array([[940.0, 150.0, 59.3], [-48.4, -768.3, 697.9], [-0.0222, 0.2773, 1.0]])


pytestmark = pytest.mark.usefixtures("pygame_display")


def ring_centre(renderer: Renderer, size, xy) -> np.ndarray:
    """The centre (px) of the bright halo ring drawn for a puck at table ``xy`` (metres)."""
    s = pygame.Surface(size)
    renderer.draw(s, Frame(seq=0, t=0.0, pucks=(Puck(1, *xy, 0.0),)))
    img = pygame.surfarray.array3d(s).astype(int).sum(axis=2)     # (x, y)
    xs, ys = np.nonzero(img > 450)
    assert len(xs) > 50, "no halo drawn"
    return np.array([(xs.min() + xs.max()) / 2, (ys.min() + ys.max()) / 2])


@pytest.mark.parametrize("xy", [(0.25, 0.2), (0.95, 0.6)])
def test_a_calibrated_puck_lands_where_the_projector_puts_it_in_a_larger_window(xy):
    """Drawn at 1920x1080 with a fit made at 1280x720, a puck's halo is at 1.5 times its fitted
    pixel (the projector stretches either mode over the same table); the fit unscaled put
    it in the window's top-left two thirds."""
    expected = apply_homography(H, np.array([xy]))[0] * 1.5
    r = Renderer(TABLE, GIVEN, homography=scaled_homography(H, ASKED, GIVEN))
    assert np.abs(ring_centre(r, GIVEN, xy) - expected).max() <= 3.0


def test_the_uncalibrated_table_fills_the_window_it_is_given():
    assert scaled_homography(None, ASKED, GIVEN) is None
    r = Renderer(TABLE, GIVEN, margin=24)
    centre = ring_centre(r, GIVEN, (0.6, 0.4))            # the table's centre
    assert np.abs(centre - np.array(GIVEN) / 2).max() <= 3.0


def test_a_window_larger_than_the_screen_is_opened_to_fit_it_and_drawn_whole():
    """A 1280x720 view on an 800x600 screen showed only its middle (an Xvfb screenshot): the
    window opens at the largest size of its shape that fits, and the whole table is in it."""
    from tabletop.display import window_size
    assert window_size((1280, 720), (1920, 1080)) == (1280, 720)
    small = window_size((1280, 720), (800, 600))
    assert small == (800, 450)
    r = Renderer(TABLE, small, margin=24)
    for corner in ((0.02, 0.02), (1.18, 0.78)):   # pucks near opposite corners of the table
        c = ring_centre(r, small, corner)
        assert 0 < c[0] < small[0] and 0 < c[1] < small[1]


@pytest.mark.parametrize("h", [
    np.array([[400.0, 0.0, 100.0], [0.0, -400.0, 600.0], [0.0, 0.0, 1.0]]),   # x 100-580 px
    np.diag([0.5, 0.5, 1.0]) @ H + np.array([[0, 0, 50.0], [0, 0, 300.0], [0, 0, 0]])])
def test_one_moment_stands_on_a_calibrated_table_wherever_the_projector_puts_it(h):
    """The ring of lights and "One moment" were centred on the window: with a projector
    throwing beyond the table they landed off it (here the table fills the left part, square
    or keystoned: there the corners' box centre is 9 px off the table's)."""
    from tabletop.frames import SourceHealth
    r = Renderer(TABLE, ASKED, homography=h)
    s = pygame.Surface(ASKED)
    down = (SourceHealth("camera", False, "cannot open camera 0"),)
    for k in range(12):
        r.draw(s, Frame(seq=k, t=k * 0.1, health=down))
    assert r.moment == 1.0
    img = pygame.surfarray.array3d(s).astype(int).sum(axis=2)      # (x, y)
    xs, ys = np.nonzero(img > 250)                                  # the lights and the words
    assert len(xs) > 200
    cx, cy = r.map.point(0.6, 0.4)                                  # the table's centre
    corners = r._corners()
    assert abs(xs.mean() - cx) < 4, (xs.mean(), cx)
    assert corners[:, 1].min() < ys.min() and ys.max() < corners[:, 1].max()


@pytest.mark.parametrize("runtime_dir", [True, False])
def test_a_display_named_but_not_there_is_refused_not_drawn_offscreen(tmp_path, runtime_dir):
    """DISPLAY names an X server that is not running (it died, it restarts): SDL falls back to
    its offscreen driver; the run is refused in one line naming the display (a kiosk's
    supervisor restarts it until the display opens) instead of drawing into no window, before
    the drawing's modules load their compiled kernels (1.14 -> 0.5 CPU s). Also without
    XDG_RUNTIME_DIR, as a system service runs: SDL probed Wayland too, and libwayland printed
    "error: XDG_RUNTIME_DIR is invalid or not set in the environment." above it."""
    import os
    import subprocess
    import sys
    cfg = tmp_path / "config.yaml"
    cfg.write_text("sources: [{kind: scripted, name: visitor, pucks: [1]}]\n"
                   "view: {size: [320, 180]}\n")
    env = {k: v for k, v in os.environ.items()
           if k not in ("SDL_VIDEODRIVER", "WAYLAND_DISPLAY", "XDG_RUNTIME_DIR")}
    env.update(DISPLAY=":4242")   # no server has that number
    if runtime_dir:
        env.update(XDG_RUNTIME_DIR=str(tmp_path))
    r = subprocess.run([sys.executable, "-X", "importtime", "-m", "tabletop", "run", "--config",
                        str(cfg), "--seconds", "1"], capture_output=True, text=True, env=env,
                       timeout=120)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    loaded = {ln.rsplit("|", 1)[-1].strip() for ln in lines if ln.startswith("import time:")}
    assert "tabletop.display" in loaded, "the display was not started by tabletop.display"
    assert not {"tabletop.view", "numba"} & loaded, "the drawing loaded before the refusal"
    err = [ln for ln in lines if not ln.startswith("import time:")]
    assert err == ["tabletop run: error: the display (DISPLAY=:4242) cannot be opened: SDL "
                   "found only its offscreen driver; start the display, or run without a "
                   "window (--headless or view.headless)"], r.stderr
