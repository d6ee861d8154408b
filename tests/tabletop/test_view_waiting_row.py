"""Reactors waiting on one spot (each engine's waiting place is the table's centre) are drawn side
by side, each seen whole, not as one blob; one that starts reacting glides from its place in the
row."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame
from tabletop.renderer import Renderer
from tests.tabletop.test_view import TABLE

pytestmark = pytest.mark.usefixtures("pygame_display")

SIZE = (1280, 720)
WAITING = [("lover", 0.08, (240, 110, 150)), ("stalker", 0.08, (120, 120, 200)),
           ("bully", 0.1, (220, 80, 40))]


def waiting(names, x: float = 0.6, y: float = 0.4) -> tuple[CharacterState, ...]:
    return tuple(CharacterState(n, x, y, 0.0, kind="reactor", size=z, color=c, valid=False,
                                label="waiting") for n, z, c in WAITING if n in names)


def drawn(characters, frames: int = 60) -> tuple[np.ndarray, Renderer]:
    """The window (x, y, rgb) after ``frames`` frames at 60 Hz of ``characters``, and the
    renderer."""
    r = Renderer(TABLE, SIZE, margin=24)
    s = pygame.Surface(SIZE)
    for k in range(frames):
        r.draw(s, Frame(seq=k, t=k / 60, characters=characters))
    return pygame.surfarray.array3d(s).astype(np.int16), r


def test_reactors_waiting_on_one_spot_are_each_seen_whole():
    """examples/reactors.yaml with its pucks not yet down: lover, stalker and bully wait at the
    table's centre. Drawn there together, the bully hid the two others: the share of each one's
    own pixels drawn as when it stands alone where it is drawn (1280x720): lover 0.034, stalker
    0.030, bully 0.793 -> 1.0, 0.949, 0.982."""
    names = [n for n, _, _ in WAITING]
    empty, _ = drawn(())
    together, r = drawn(waiting(names))
    seen = {}
    for name in names:
        dx, dy = r.lives.presences[name].offset(59 / 60)
        alone, _ = drawn(waiting([name], 0.6 + dx, 0.4 + dy))
        own = np.abs(alone - empty).sum(axis=2) > 60             # its body (and eyes)
        assert own.sum() > 1000, name
        same = np.abs(together - alone).sum(axis=2) <= 30
        seen[name] = round(float(same[own].mean()), 3)
    assert min(seen.values()) > 0.9, seen


def test_a_single_waiting_reactor_stands_at_its_place():
    img, _ = drawn(waiting(["bully"]))
    own = np.abs(img - drawn(())[0]).sum(axis=2) > 60
    xs, ys = np.nonzero(own)
    assert abs(xs.mean() - 640) < 8 and abs(ys.mean() - 360) < 8


def test_a_reactor_leaving_the_row_glides_from_its_place_in_it():
    """The lover (top of the row) starts reacting 20 cm right of the centre: its first frame
    is drawn where it waited, above the centre, not at the centre under the others."""
    r = Renderer(TABLE, SIZE, margin=24)
    s = pygame.Surface(SIZE)
    three = waiting([n for n, _, _ in WAITING])
    for k in range(60):
        r.draw(s, Frame(seq=k, t=k / 60, characters=three))
    lover = CharacterState("lover", 0.8, 0.4, 0.0, kind="reactor", size=0.08,
                           color=(240, 110, 150), valid=True)
    pr = r.lives.presences
    places = []
    for k in range(60, 90):
        r.draw(s, Frame(seq=k, t=k / 60, characters=(lover, *three[1:])))
        ox, oy = pr["lover"].offset(k / 60)
        places.append((0.8 + ox, 0.4 + oy))
    assert places[0][1] > 0.4 + 0.05 and places[0][0] < 0.62     # in the row, above the centre
    assert abs(places[-1][0] - 0.8) < 0.005 and abs(places[-1][1] - 0.4) < 0.005
