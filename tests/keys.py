"""Key presses posted to pygame's event queue, as a keyboard gives them to the view."""

import pygame


def key(k: int) -> None:
    """Post one press of key ``k`` (a ``pygame.K_*`` code) with no modifier."""
    pygame.event.post(pygame.event.Event(pygame.KEYDOWN, key=k, mod=0, unicode="", scancode=0))
