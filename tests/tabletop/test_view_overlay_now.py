"""The operator panel says what the frame shows: a character's line changes on the very frame
its action begins or ends, while its figures (progress, probability) wait for the overlay's
refresh, so the panel is not made again every frame."""

import time

import pygame
import pytest

import tabletop.view as view_module
from tabletop.config import validate_config
from tabletop.frames import CharacterState, Frame
from tabletop.view import OVERLAY_REFRESH_S, ProjectorView, told
from tests.tabletop.test_view_overlay import stats_with_stages

pytestmark = pytest.mark.usefixtures("pygame_display")


def dancer(k: int) -> CharacterState:
    """Frame ``k``'s dancer: resting until 30, acting (a line, its progress rising) until 60,
    then holding its last pose, not acting (MOP's hold after a gesture's end)."""
    acting = 30 <= k < 60
    label = f"line {(k - 30) / 30:4.2f} p=0.9{k % 10}" if acting else "no action"
    return CharacterState("dancer", 0.6, 0.4, 0.0, size=0.1, color=(240, 170, 60),
                          action="line" if k >= 30 else None, valid=acting, label=label)


def test_the_panel_names_the_action_on_the_frame_it_begins_and_ends(monkeypatch):
    # one step of the refresh per frame: a refresh takes 26 frames, as on a loaded machine
    monkeypatch.setattr(view_module, "OVERLAY_SLICE_S", 0.0)
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"size": [640, 360], "headless": True, "overlay": True}})
    view = ProjectorView((1.2, 0.8), cfg["view"], stats=stats_with_stages(6))
    try:
        panels, changed = set(), {}
        before = None
        for k in range(90):
            if k in (10, 40, 70):
                time.sleep(OVERLAY_REFRESH_S + 0.01)     # a refresh starts on this frame
            view.consume(Frame(seq=k, t=k / 60, characters=(dancer(k),)))
            drawn = [line for line in view.renderer._overlay_key if line.startswith("dancer:")]
            c = dancer(k)
            assert drawn == [f"dancer: {c.label}"] if not c.valid else \
                drawn[0].startswith("dancer: line "), (k, drawn)
            panels.add(view.renderer._overlay_key)
            place = view.renderer.panel
            now = pygame.surfarray.array3d(view.screen.subsurface(place)).copy()
            if before is not None and before.shape == now.shape:
                changed[k] = bool((now != before).any())
            before = now
        # on the screen: the panel's pixels changed on the frames the action began and ended
        assert changed[30] and changed[60]
        # the figures wait: a panel per refresh and per change of words, not one per frame
        assert len(panels) <= 8, len(panels)
    finally:
        view.close()


def test_what_the_lines_say_is_their_words_not_their_figures():
    a = CharacterState("salamander", 0, 0, 0, action="line", valid=True, label="line 0.36 p=1.00")
    b = CharacterState("salamander", 0, 0, 0, action="line", valid=True, label="line 0.41 p=0.97")
    c = CharacterState("salamander", 0, 0, 0, action="line", valid=False, label="no action")
    assert told(Frame(seq=1, t=0.0, characters=(a,))) == told(Frame(seq=2, t=0.1, characters=(b,)))
    assert told(Frame(seq=1, t=0.0, characters=(a,))) != told(Frame(seq=2, t=0.1, characters=(c,)))
