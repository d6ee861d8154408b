"""The operator panel beside characters: its lines wrap to end before a character under its
end, before a character's body rather than its glow, and its corner is chosen by the bodies it
hides, not the glows' bounds."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame
from tests.tabletop.test_view import rgb

pytestmark = pytest.mark.usefixtures("pygame_display")


def test_a_long_source_line_wraps_to_end_the_panel_before_a_character_under_its_end():
    """At 1280x720 a source's line with its "(ignored: ...)" counts made the panel 600 px
    wide; a character under its end showed through there and the line's last words read as
    text past the panel's edge (15 text pixels over the character). Its lines wrap narrower:
    every text pixel lies on the panel, none over the character."""
    from tabletop.renderer import Renderer
    r = Renderer((1.2, 0.8), (1280, 720), margin=24)
    target = pygame.Surface((1280, 720))
    lines = ["tick 814   running 13.6 s", "60.0 fps   skipped 11   errors 0",
             *[f"  stage{i}\t{0.5:6.2f} ms median\t{13.5:6.2f} ms p99" for i in range(8)],
             "source tuio: ok  listening on 127.0.0.1:39336; TUIO from touch@frame (ignored: "
             "3 non finite)  age 12 ms", "poser: posing view 90,15 touches 1"]
    character = pygame.Rect(475, 200, 400, 500)
    panel = r.draw_overlay(target, lines, avoid=[character], must=[])
    ys, xs = np.nonzero(rgb(target).sum(axis=2) > 100)
    assert len(xs) > 1000                                     # the text is drawn
    assert panel.collidepoint(xs.min(), ys.min()) and panel.collidepoint(xs.max(), ys.max())
    over = (xs >= character.left) & (ys >= character.top) & (ys < character.bottom)
    assert not over.any() and not panel.colliderect(character)
    assert panel.h < 720 // 2                                # one compact panel


@pytest.mark.parametrize("below", [False, True])
def test_the_panel_wraps_to_end_before_a_characters_body_not_its_glow(below):
    """A character's glow reaches about a third of its size beyond its body: a reactor 0.2 m
    long at 1280x720, glow 309 px wide, body 189 px. With the glow under the panel's end the
    panel was not narrowed (the glow left it under 320 px, or, with another character
    ``below`` it, the narrower and taller panel hid more of the glows) and its figures ran over
    the body; its lines wrap to end before the body, over the glow's rim (below, the narrower
    panel reaches 18 rows into the other body: 3,402 body pixels hidden instead of 5,103)."""
    from tabletop.drawing import characters
    from tabletop.renderer import Renderer
    stages = ("capture-to-render", "inputs", "engines", "sinks", "tick", "engine:mop",
              "sink:view")
    lines = ["tick 247   running 6.0 s", "43.3 fps   skipped 110   errors 0",
             *[f"  {name}\t{17.8:6.2f} ms median\t{66.16:6.2f} ms p99" for name in stages],
             "source performers: ok  scripted visitor  age 0 ms",
             *[f"{name}: no action" for name in ("dancer", "bird", "face", "gecko", "mime")]]
    near = CharacterState("near", 0.37, 0.62, 0.0, size=0.2, color=(240, 110, 150))
    places = [(1.02, 0.62), (0.16, 0.18), (1.02, 0.18)] + ([(0.16, 0.24)] if below else [])
    others = [CharacterState(f"c{i}", x, y, 0.0, size=0.2, color=(240, 110, 150))
              for i, (x, y) in enumerate(places)]
    drawn = []
    for overlay in (None, lines):
        r = Renderer((1.2, 0.8), (1280, 720), margin=24)
        target = pygame.Surface((1280, 720))
        for k in range(31):
            r.draw(target, Frame(seq=k, t=k / 20, characters=(near, *others)),
                   overlay if k == 30 else None)
        drawn.append(rgb(target).astype(int))
    assert r.panel.topleft == (8, 8)                           # its corner: the top-left
    body = characters.bodies([near], r.map)[0]
    assert not r.panel.colliderect(body), (r.panel, body)
    cut = (slice(body.top, body.bottom), slice(body.left, body.right))
    assert (drawn[1][cut] == drawn[0][cut]).all()              # nothing drawn over the body
    hidden = sum(r.panel.clip(b).w * r.panel.clip(b).h
                 for b in characters.bodies([near, *others], r.map))
    assert hidden <= (3402 if below else 0), hidden


def test_the_panel_stays_over_a_glows_rim_rather_than_move_over_a_body():
    """The panel's corner is chosen by the bodies it hides, not the glows' bounds: a large
    character's glow reaching under the top-left panel (101 x 188 px) sent it to the top-right
    corner, over a small character's body (its glow 97 x 97 px); it stays top-left, over no
    body."""
    from tabletop.drawing import characters
    from tabletop.renderer import Renderer
    r = Renderer((1.2, 0.8), (1280, 720), margin=24)
    target = pygame.Surface((1280, 720))
    lines = ["tick 814   running 13.6 s", "60.0 fps   skipped 11   errors 0",
             *[f"  stage{i}\t{0.5:6.2f} ms median\t{13.5:6.2f} ms p99" for i in range(8)]]
    chars = (CharacterState("large", 0.39, 0.65, 0.0, size=0.35, color=(240, 110, 150)),
             CharacterState("small", 1.148, 0.71, 0.0, size=0.06, color=(240, 110, 150)),
             CharacterState("c0", 0.16, 0.18, 0.0, size=0.2, color=(240, 110, 150)),
             CharacterState("c1", 1.02, 0.18, 0.0, size=0.2, color=(240, 110, 150)))
    for k in range(31):
        r.draw(target, Frame(seq=k, t=k / 20, characters=chars), lines if k == 30 else None)
    assert r.panel.topleft == (8, 8), r.panel
    assert r.panel.collidelist(characters.bodies(chars, r.map)) == -1
