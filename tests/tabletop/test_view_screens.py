"""The projector view's screens, rendered offscreen: the "one moment" screen while every
camera is down (calm, nothing technical, characters stepped back) and the idle look."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame, Puck, SourceHealth
from tabletop.view import cameras_down, overlay_lines
from tests.tabletop.test_view import SIZE, brightness, new_renderer, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")


def test_one_moment_screen_while_every_camera_is_down_and_gone_when_one_recovers():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    ok = (SourceHealth("cam_a", True), SourceHealth("cam_b", True))
    half = (SourceHealth("cam_a", False, "reconnecting in 2 s"), SourceHealth("cam_b", True))
    down = (SourceHealth("cam_a", False, "reconnecting in 2 s"),
            SourceHealth("cam_b", False, "no frames"))
    assert not cameras_down(Frame(0, 0.0, health=half)) and cameras_down(Frame(0, 0.0, health=down))
    c = CharacterState("lover", 0.95, 0.65, 0.0, size=0.1, color=(240, 110, 150))
    text_box = (slice(360, 470), slice(490, 790))     # under the screen's centre

    def frame(k, t, health):
        return Frame(seq=k, t=t, health=health, characters=(c,),
                     pucks=(Puck(1, 0.3, 0.3, 0.0),))
    for k in range(10):
        r.draw(s, frame(k, k * 0.1, half))
    calm = rgb(s)[text_box].sum(axis=2).max()
    assert r.moment == 0.0
    for k in range(10, 30):
        r.draw(s, frame(k, k * 0.1, down))
    img = rgb(s)
    assert r.moment == 1.0 and img[text_box].sum(axis=2).max() > calm + 200    # the words
    assert brightness(img, r.map.point(0.3 + 0.04, 0.3)) < 200                  # table dimmed
    for k in range(30, 45):
        r.draw(s, frame(k, k * 0.1, ok))
    assert r.moment == 0.0 and rgb(s)[text_box].sum(axis=2).max() <= calm + 30


def test_one_moment_screen_tells_visitors_nothing_technical():
    # the source's own words are for the operator (overlay, log, status), not the gallery: the
    # screen a visitor sees is the same whatever the camera says, and the overlay still says it
    technical = "cannot open camera 7; reconnecting in 3.1 s (uncalibrated)"
    shown = {}
    for message in (technical, "no frames", ""):
        r, s = new_renderer(), pygame.Surface(SIZE)
        for k in range(20):                      # 2 s down: the screen has faded fully in
            r.draw(s, Frame(seq=k, t=k * 0.1, health=(SourceHealth("overhead", False, message),)))
        assert r.moment == 1.0
        shown[message] = rgb(s)
    words = shown[""][360:470, 490:790].sum(axis=2)
    assert words.max() > 200                      # "One moment" is drawn
    for message in (technical, "no frames"):
        assert np.array_equal(shown[message], shown[""]), message
    down = Frame(seq=0, t=0.0, health=(SourceHealth("overhead", False, technical),))
    assert any(technical in line for line in overlay_lines(down, None))


def test_no_invitation_to_play_under_the_one_moment_screen():
    # every camera down: the table cannot see a puck, so "put a puck on the table" (and its
    # motes) must not show under "One moment"
    r = new_renderer()
    s = pygame.Surface(SIZE)
    down = (SourceHealth("overhead", False, "cannot open camera 0; reconnecting in 2 s"),)
    for k in range(120):                              # 12 s of an empty table, camera down
        r.draw(s, Frame(seq=k, t=k * 0.1, health=down))
    assert r.moment == 1.0 and r.idle == 0.0
    lo, hi = r._corners().min(axis=0), r._corners().max(axis=0)
    y = int((lo[1] + hi[1]) / 2 + 0.3 * (hi[1] - lo[1]))  # the invitation's line
    x0, x1 = int(lo[0] + 0.3 * (hi[0] - lo[0])), int(lo[0] + 0.7 * (hi[0] - lo[0]))
    band = rgb(s)[y - 15:y + 15, x0:x1].sum(axis=2)
    assert band.max() < 60, band.max()                # no words there, only the dim table
    ok = (SourceHealth("overhead", True),)
    for k in range(120, 200):                         # back, nobody at the table: it invites
        r.draw(s, Frame(seq=k, t=k * 0.1, health=ok))
    assert r.moment == 0.0 and r.idle == 1.0
    assert rgb(s)[y - 15:y + 15, x0:x1].sum(axis=2).max() > 150


def test_idle_look_when_nobody_plays_and_not_while_someone_does():
    r = new_renderer()
    s = pygame.Surface(SIZE)
    for k in range(40):
        r.draw(s, Frame(seq=k, t=k * 0.1, pucks=(Puck(1, 0.3 + 0.005 * k, 0.3, 0.0, vx=0.05),)))
    assert r.idle == 0.0
    for k in range(40, 120):
        r.draw(s, Frame(seq=k, t=k * 0.1))
    assert r.idle == 1.0
    r.draw(s, Frame(seq=120, t=12.1, pucks=(Puck(1, 0.5, 0.3, 0.0, vx=0.1),)))
    for k in range(121, 140):
        r.draw(s, Frame(seq=k, t=k * 0.1, pucks=(Puck(1, 0.5, 0.3, 0.0, vx=0.1),)))
    assert r.idle == 0.0


def test_characters_step_back_under_the_one_moment_screen():
    # every camera down: a reactor waiting for its main stands at the table's centre, right
    # under the ring of lights; the calm screen shows alone, and the character is back with
    # the camera
    r = new_renderer()
    s = pygame.Surface(SIZE)
    c = CharacterState("lover", 0.6, 0.4, 0.0, size=0.08, color=(240, 110, 150), valid=False)
    down = (SourceHealth("overhead", False, "cannot open camera 0; reconnecting in 2 s"),)
    ok = (SourceHealth("overhead", True),)
    x, y = r.map.point(0.6, 0.4)
    body = (slice(int(y) - 25, int(y) + 25), slice(int(x) - 40, int(x) + 40))

    def pink(img):   # pixels of the body's hue: red above blue and green (the ring is blue)
        a = img[body]
        return int(((a[..., 0] - np.maximum(a[..., 1], a[..., 2])) > 5).sum())
    for k in range(30):
        r.draw(s, Frame(seq=k, t=k * 0.1, health=ok, characters=(c,)))
    assert pink(rgb(s)) > 1500                # measured 2367 pixels of the body
    for k in range(30, 60):
        r.draw(s, Frame(seq=k, t=k * 0.1, health=down, characters=(c,)))
    assert r.moment == 1.0 and pink(rgb(s)) == 0   # was 2203: a dim body under the ring
    for k in range(60, 90):
        r.draw(s, Frame(seq=k, t=k * 0.1, health=ok, characters=(c,)))
    assert r.moment == 0.0 and pink(rgb(s)) > 1500
