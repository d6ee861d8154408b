"""The kiosk's view: fullscreen, no overlay until the service key, Esc only in service mode."""

import threading

import pygame

from tabletop.config import validate_config
from tabletop.frames import Frame
from tabletop.kiosk.runner import kiosk_view
from tabletop.loop import CommandQueue
from tabletop.view import ProjectorView

from tests.keys import key


def test_service_key_shows_the_overlay_and_only_then_esc_quits():
    cfg = validate_config({"sources": [{"kind": "scripted"}], "view": {"overlay": True}})
    cfg = kiosk_view(cfg, kiosk=True)
    assert cfg["view"]["fullscreen"] is True and cfg["view"]["overlay"] is False
    stop = threading.Event()
    view = ProjectorView((1.2, 0.8), dict(cfg["view"], size=[320, 180]), commands=CommandQueue(),
                         stop=stop, headless=True)
    view.kiosk, view.service_key = True, pygame.K_F12
    try:
        for k in (pygame.K_o, pygame.K_F1, pygame.K_ESCAPE):   # a visitor's keyboard
            key(k)
            view.consume(Frame(seq=0, t=0.0))
        assert not view.show_overlay and not stop.is_set()
        key(pygame.K_F12)
        view.consume(Frame(seq=1, t=0.1))
        assert view.show_overlay
        key(pygame.K_ESCAPE)
        view.consume(Frame(seq=2, t=0.2))
        assert stop.is_set()
    finally:
        view.close()


def test_f2_names_the_item_in_play():
    q = CommandQueue()
    cfg = validate_config({"sources": [{"kind": "scripted"}]})
    view = ProjectorView((1.2, 0.8), dict(cfg["view"], size=[320, 180]), commands=q,
                         headless=True)
    try:
        key(pygame.K_F2)
        for ch in "shy-1":
            pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=ord(ch), mod=0, unicode=ch,
                                                 scancode=0))
        key(pygame.K_BACKSPACE)
        pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=ord("2"), mod=0, unicode="2",
                                             scancode=0))
        view.consume(Frame(seq=0, t=0.0))
        assert q.drain() == ()                  # typing a name sends no designer keys (no "s")
        key(pygame.K_RETURN)
        view.consume(Frame(seq=1, t=0.1))
        assert q.drain() == ("designer.rename:shy-2",)
    finally:
        view.close()
