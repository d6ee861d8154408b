"""The operator panel says what the frame shows: a character's line changes on the very frame
its action begins or ends, while its figures (progress, probability) wait for the overlay's
refresh, so the panel is not made again every frame."""

import time

import numpy as np
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


def suspecting(k: int) -> CharacterState:
    """Frame ``k``'s salamander: suspecting an action (its hinted pose shown) whose name
    changes every frame, as MOP's likeliest hint may; acting (a line) from frame 60 on."""
    acting = k >= 60
    pts = np.array([[0.5, 0.4], [0.6, 0.4], [0.7, 0.4]])
    hint = ("wave", "circle")[k % 2]
    return CharacterState("salamander", 0.6, 0.4, 0.0, kind="creature", size=0.3, points=pts,
                          bones=((0, 1), (1, 2)), color=(90, 220, 120), valid=acting,
                          action="line" if acting else None,
                          label="line 0.20 p=0.90" if acting else "no action",
                          hints=() if acting else ((hint, 0.9, 0.4),),
                          hint_points=None if acting else pts + (0.0, 0.05))


def test_the_panel_names_a_shown_hint_steadily_and_not_once_its_action_drives():
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"size": [640, 360], "headless": True, "overlay": True}})
    view = ProjectorView((1.2, 0.8), cfg["view"], stats=stats_with_stages(6))
    try:
        said, refreshes = [], set()
        for k in range(90):
            if k in (15, 35, 70):
                time.sleep(OVERLAY_REFRESH_S + 0.01)     # a refresh starts on this frame
            view.consume(Frame(seq=k, t=k / 60, characters=(suspecting(k),)))
            refreshes.add(view._overlay_t)
            said += [line for line in view.renderer._overlay_key
                     if line.startswith("salamander:")]
        likely = [line for line in said[:60] if "likely: " in line]
        # once a refresh found the hint shown, the line names its action ...
        assert likely and all(line.startswith("salamander: no action   likely: ")
                              for line in likely), said[:60]
        # ... changing at most once a refresh, though the hint's name changed every frame
        changes = sum(a != b for a, b in zip(said, said[1:]))
        assert changes <= len(refreshes) + 1, (changes, len(refreshes), said)
        # acting, it names the action it plays, not what was suspected
        assert all("likely" not in line for line in said[60:]), said[60:]
        assert said[60].startswith("salamander: line ")
    finally:
        view.close()
