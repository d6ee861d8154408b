"""The operator panel keeps its shape while a body reaches briefly near or under it: a
narrowing or widening is taken once the other shape has hidden clearly less for DWELL_S, at
once only when it hides AT_ONCE_PX fewer body pixels (tabletop.drawing.panel_room)."""

import pygame
import pytest

from tabletop.drawing import characters, panel_room
from tabletop.frames import CharacterState, Frame
from tabletop.renderer import Renderer

pytestmark = pytest.mark.usefixtures("pygame_display")

W, H = 1280, 720
STAGES = ("capture-to-render", "inputs", "engines", "sinks", "tick", "engine:mop", "sink:view")
LINES = ["tick 247   running 6.0 s", "43.3 fps   skipped 110   errors 0",
         *[f"  {name}\t{17.8:6.2f} ms median\t{66.16:6.2f} ms p99" for name in STAGES],
         "source performers: ok  scripted visitor  age 0 ms",
         *[f"{name}: no action" for name in ("dancer", "bird", "face", "gecko", "mime")]]


def test_a_body_stepping_near_the_narrowed_panels_end_leaves_it_as_it_is():
    """A body 0.2 m long beside the narrowed top-left panel steps 2.4 cm towards it for
    0.5 s: its left edge at 332 px leaves no 320 px width to wrap to, and the panel widened
    (371 px) over the body, then narrowed again (2 changes, 8,883 body px hidden a frame);
    the narrowed panel, ending at 328 px at most, hides none of it and stays."""
    r = Renderer((1.2, 0.8), (W, H), margin=24)
    target = pygame.Surface((W, H))
    others = [CharacterState(f"c{i}", x, y, 0.0, size=0.2, color=(240, 110, 150))
              for i, (x, y) in enumerate([(1.02, 0.62), (0.16, 0.18), (1.02, 0.18)])]
    places, hidden = [], 0
    for k in range(50):
        x = 0.346 if 20 <= k < 30 else 0.37
        near = CharacterState("near", x, 0.62, 0.0, size=0.2, color=(240, 110, 150))
        r.draw(target, Frame(seq=k, t=k / 20, characters=(near, *others)), LINES)
        body = characters.bodies([near], r.map)[0]
        if k == 25:
            assert body.left == 332, body                    # the step, as measured
        places.append(tuple(r.panel))
        hidden += k > 0 and r.panel.clip(body).w * r.panel.clip(body).h
    # narrowed in the top-left: wrapped to 320 px, its figures bare (test_view_panel_bare.py)
    # leave it 296 px wide (320 when its stage rows split in two)
    assert places[1][:2] == (8, 8) and places[1][2] <= 320, places[1]
    assert len(set(places[1:])) == 1, sorted(set(places))
    assert hidden == 0


def _place(room: panel_room.PanelPlace, avoid: list[pygame.Rect], t: float) -> pygame.Rect:
    img = pygame.Surface((371, 290))
    corners = [(8, 8), (W - 379, 8), (8, H - 298), (W - 379, H - 298)]
    place, _ = room(corners, img, avoid, [], [], None, (W, H),
                    lambda width: pygame.Surface((width, 426)), t)
    return place


def test_a_shape_hiding_clearly_less_is_taken_after_the_dwell_or_at_once_when_much_less():
    """Held narrowed (320 x 426 px), the wide panel (371 x 290) hiding 1,100 fewer pixels is
    taken after DWELL_S of frames, not before; hiding 2,300 fewer (AT_ONCE_PX), at once."""
    busy = [pygame.Rect(W - 379, 8, 371, 290), pygame.Rect(8, 600, 371, 112),
            pygame.Rect(W - 379, 600, 371, 112)]                  # the other corners

    for under, wide_at in ((pygame.Rect(100, 320, 30, 40), 0.05 + panel_room.DWELL_S),
                           (pygame.Rect(100, 320, 60, 40), 0.05)):    # first seen at 0.05 s
        room = panel_room.PanelPlace()
        assert _place(room, busy + [pygame.Rect(340, 50, 60, 50)], 0.0).size == (320, 426)
        reach = busy + [pygame.Rect(330, 50, 10, 10), under]   # no 320 px width left
        for k in range(1, 40):
            t = k * 0.05
            wide = _place(room, reach, t).size == (371, 290)
            if abs(t - wide_at) > 0.01:                         # (the frame at the edge)
                assert wide == (t > wide_at), (under, t)
