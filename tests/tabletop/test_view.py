"""The projector view, rendered offscreen: pucks where they are, headings the right way."""

import math

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame, Puck
from tabletop.view import Renderer, TableToScreen, overlay_lines, puck_color

TABLE = (1.2, 0.8)
SIZE = (1280, 720)


@pytest.fixture(scope="module")
def renderer():
    pygame.display.init()
    yield Renderer(TABLE, SIZE, margin=24, puck_radius=0.03)
    pygame.display.quit()


def render(renderer, frame):
    surface = pygame.Surface(SIZE)
    renderer.draw(surface, frame)
    return surface


def pixel(surface, xy):
    return tuple(surface.get_at((int(round(xy[0])), int(round(xy[1]))))[:3])


def test_table_fit_puts_origin_bottom_left_and_y_up():
    m = TableToScreen(TABLE, SIZE, margin=24)
    x0, y0 = m.point(0.0, 0.0)
    x1, y1 = m.point(1.2, 0.8)
    assert x0 < x1 and y0 > y1  # x right, y up the screen
    assert min(x0, SIZE[0] - x1) >= 24 - 1e-9 and min(SIZE[1] - y0, y1) >= 24 - 1e-9
    # aspect kept: a metre is the same number of pixels along both axes
    assert (x1 - x0) / 1.2 == pytest.approx((y0 - y1) / 0.8)


@pytest.mark.parametrize("angle", [0.0, math.pi / 2, 2.5, -1.0])
def test_puck_colour_under_its_position_and_heading_on_the_right_side(renderer, angle):
    puck = Puck(3, 0.4, 0.3, angle)
    surface = render(renderer, Frame(seq=0, t=0.0, pucks=(puck,)))
    m = renderer.map
    r = 0.03
    # The puck's colour covers its body away from the heading marker.
    behind = m.point(0.4 - 0.5 * r * math.cos(angle), 0.3 - 0.5 * r * math.sin(angle))
    assert pixel(surface, behind) == puck_color(3)
    # The white heading marker lies ahead of the centre, not behind it.
    ahead = m.point(0.4 + 0.7 * r * math.cos(angle), 0.3 + 0.7 * r * math.sin(angle))
    assert pixel(surface, ahead) == (255, 255, 255)
    opposite = m.point(0.4 - 0.7 * r * math.cos(angle), 0.3 - 0.7 * r * math.sin(angle))
    assert pixel(surface, opposite) == puck_color(3)
    # Outside the puck: the table.
    outside = m.point(0.4 + 2.5 * r, 0.3)
    assert pixel(surface, outside) != puck_color(3)


def test_coasting_puck_is_a_ring(renderer):
    surface = render(renderer, Frame(seq=0, t=0.0, pucks=(Puck(2, 0.6, 0.4, 0.0,
                                                                state="coasting"),)))
    m = renderer.map
    rim = m.point(0.6, 0.4 + 0.028)
    centre = m.point(0.6, 0.4)
    assert pixel(surface, rim) == puck_color(2)
    assert pixel(surface, centre) != puck_color(2)


def test_character_drawn_under_the_puck_and_pointing_its_heading(renderer):
    c = CharacterState("lover", 0.8, 0.5, math.pi, size=0.1, color=(200, 40, 200))
    surface = render(renderer, Frame(seq=0, t=0.0, characters=(c,)))
    m = renderer.map
    assert pixel(surface, m.point(0.8 - 0.45 * 0.1, 0.5)) == (200, 40, 200)  # nose at -x
    assert pixel(surface, m.point(0.8 + 0.62 * 0.1, 0.5)) != (200, 40, 200)  # nothing past the tail
    puck = Puck(1, 0.8, 0.5, 0.0)
    both = render(renderer, Frame(seq=0, t=0.0, pucks=(puck,), characters=(c,)))
    assert pixel(both, m.point(0.8, 0.49)) == puck_color(1)  # the puck is on top


def test_articulated_character_draws_its_bones(renderer):
    pts = np.array([[0.2, 0.2], [0.4, 0.2]])
    c = CharacterState("stick", 0.3, 0.2, 0.0, kind="skeleton", points=pts, bones=((0, 1),),
                       color=(10, 250, 10))
    surface = render(renderer, Frame(seq=0, t=0.0, characters=(c,)))
    assert pixel(surface, renderer.map.point(0.3, 0.2)) == (10, 250, 10)


def test_invalid_character_is_dimmed(renderer):
    c = CharacterState("x", 0.5, 0.5, 0.0, size=0.1, color=(240, 180, 60), valid=False)
    surface = render(renderer, Frame(seq=0, t=0.0, characters=(c,)))
    assert pixel(surface, renderer.map.point(0.5, 0.5)) == (80, 60, 20)


def test_overlay_lists_rates_and_sources():
    from tabletop.frames import SourceHealth
    from tabletop.loop import LoopStats

    st = LoopStats()
    for i in range(10):
        st.record("engines", 0.001)
        st.tick_times.append(i / 60.0)
    f = Frame(seq=5, t=1.0, health=(SourceHealth("camera", False, "reconnecting in 2 s", 3.0),))
    text = "\n".join(overlay_lines(f, st))
    assert "60.0 fps" in text and "engines" in text and "1.00 ms" in text
    assert "camera: DOWN" in text and "reconnecting" in text


def test_sprite_is_drawn_rotated_to_the_heading(tmp_path):
    """A sprite facing +x, half red (front) half blue (back), turned to face +y on the table."""
    img = pygame.Surface((40, 20))
    img.fill((0, 0, 255))
    img.fill((255, 0, 0), pygame.Rect(20, 0, 20, 20))
    path = tmp_path / "bug.png"
    pygame.image.save(img, str(path))
    pygame.display.init()
    r = Renderer(TABLE, SIZE, margin=24, sprites={"bug": path})
    c = CharacterState("bug", 0.6, 0.4, math.pi / 2, size=0.1)
    surface = render(r, Frame(seq=0, t=0.0, characters=(c,)))
    front = r.map.point(0.6, 0.4 + 0.025)
    back = r.map.point(0.6, 0.4 - 0.025)
    assert pixel(surface, front) == (255, 0, 0)
    assert pixel(surface, back) == (0, 0, 255)
