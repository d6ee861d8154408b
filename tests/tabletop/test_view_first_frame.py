"""The projector view makes its static table when it opens, before the loop starts: the run's
first tick is drawn as quickly as the next ones, not 0.15-0.5 s late (the table's soft light,
a 480 px glow, made in the first frame drawn)."""

import numpy as np
import pygame
import pytest

import tabletop.renderer as renderer_module
from tabletop.config import validate_config
from tabletop.drawing import screens
from tabletop.frames import Frame
from tabletop.view import ProjectorView

from tests.tabletop.test_view import rgb

pytestmark = pytest.mark.usefixtures("pygame_display")


def test_the_table_is_made_when_the_view_opens_not_in_the_first_frame(monkeypatch):
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"size": [1280, 720], "headless": True}})
    view = ProjectorView((1.2, 0.8), cfg["view"])
    try:
        made = []
        monkeypatch.setattr(renderer_module, "table_surface",
                            lambda *a: made.append(a) or screens.table_surface(*a))
        for k in range(3):
            view.consume(Frame(seq=k, t=k / 60))
        # made when the view opened, not in a frame (measured: the first frame 280 ms
        # before, 11 ms after, headless on 2 cores under load; the next ones 1-12 ms)
        assert made == []
        # and the frame drawn is the table: its centre lit as the static table's
        img = rgb(view.screen).astype(int)
        table = rgb(view.renderer._static).astype(int)
        assert np.abs(img[360, 640] - table[360, 640]).max() <= 2
        assert img[360, 640].sum() > 30     # the table's light, not black
    finally:
        view.close()


def test_the_configured_characters_glows_are_made_when_the_view_opens(monkeypatch):
    """examples/mop.yaml drew 7 new glow sizes in its 3rd-5th frames (15-34 ms of them at load
    3, headless and in a window); its 5 known sizes are made when the view opens (a hybrid's
    face's size is known only from its points: its glow is still made when first drawn)."""
    from tabletop.drawing import primitives as P
    from tabletop.drawing.characters import configured_parts, glow_radius
    mop = {"kind": "mop", "characters": [
        {"kind": "skeleton", "size": 0.3}, {"kind": "sprite", "size": 0.15},
        {"kind": "face", "size": 0.22}, {"kind": "hybrid", "size": 0.26}]}
    parts = configured_parts([mop, {"kind": "puppet_master", "size": 0.08}])
    assert parts == [("figure", 0.3), ("figure", 0.15), ("face", 0.22), ("figure", 0.26),
                     ("reactor", 0.08)]
    monkeypatch.setattr(P, "_glow_bases", {})     # none made by earlier tests
    cfg = validate_config({"sources": [{"kind": "scripted"}],
                           "view": {"size": [1280, 720], "headless": True}})
    view = ProjectorView((1.2, 0.8), cfg["view"], parts=parts)
    try:
        ppm = view.renderer.map.scale_at(0.6, 0.4)
        made = []
        monkeypatch.setattr(P, "_white_light", lambda v: made.append(len(v)) or
                            P.fast(pygame.surfarray.make_surface(np.zeros((*v.shape, 3)))))
        for part, size in parts:       # as each character first shows, fading in
            P.glow_surface(glow_radius(part, size, ppm), (240, 170, 60), 0.1)
        # every size made when the view opened (measured headless, 2 cores at load 3: 5 new sizes
        # 1-25 ms in the loop before; a tint each after, a copy and a fill)
        assert made == []
        assert len(P._glow_bases) >= 5
    finally:
        view.close()
