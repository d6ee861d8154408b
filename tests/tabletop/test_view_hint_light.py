"""A hinted pose (MOP early feedback) is faint light added to the table: where it crosses its
character's glow it brightens it, never puts it out (a dark shadow of the pose, pupils darker
than the light around them)."""

import numpy as np
import pygame
import pytest

from tabletop.frames import CharacterState, Frame
from tabletop.view import Renderer

from tests.tabletop.test_view import SIZE, TABLE, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

BONES = ((0, 1), (1, 2))


def creature(hint: bool) -> CharacterState:
    """A resting creature along x at y = 0.4 m; hinted, its suspected pose lies 4 cm above it,
    inside its glow (radius 0.42 of its size: 12.6 cm) and clear of its body."""
    pts = np.array([[0.5, 0.4], [0.6, 0.4], [0.7, 0.4]])
    extra = dict(hints=(("wave", 0.9, 0.4),), hint_points=pts + (0.0, 0.04)) if hint else {}
    return CharacterState("c", 0.6, 0.4, 0.0, kind="creature", size=0.3, points=pts,
                          bones=BONES, color=(90, 220, 120), valid=False, **extra)


def drawn(hint: bool) -> np.ndarray:
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    for k in range(30):       # a second: the hint faded in (0.15 s time constant)
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=(creature(hint),)))
    return rgb(s).astype(int)


def test_a_hinted_pose_over_the_glow_only_adds_light():
    plain, hinted = drawn(False), drawn(True)
    diff = hinted.sum(axis=2) - plain.sum(axis=2)
    # measured before: the faint pose painted in the table's colour over the glow, down to
    # 36 darker (of 765) along its limbs and pupils; now it only adds (rounding: at most 3)
    assert diff.min() >= -3
    assert (diff > 30).sum() > 300     # and it shows: a faint pose, not nothing


def test_added_light_adds_and_leaves_its_scratch_black():
    from tabletop.drawing.light import AddedLight
    light = AddedLight()
    s = pygame.Surface((200, 100))
    s.fill((40, 40, 50))
    r = light.add(s, lambda k: pygame.draw.circle(k, (100, 60, 20), (50, 50), 20))
    got = rgb(s).astype(int)
    assert r.w == 40 and got[50, 50].tolist() == [140, 100, 70]    # added onto the ground
    assert got[50, 150].tolist() == [40, 40, 50]
    # the next light drawn elsewhere does not carry the first along
    light.add(s, lambda k: pygame.draw.circle(k, (10, 10, 10), (150, 50), 20))
    again = rgb(s).astype(int)
    assert again[50, 50].tolist() == [140, 100, 70] and again[50, 150].tolist() == [50, 50, 60]


@pytest.mark.parametrize("rim", [2, 3])
def test_the_compiled_outline_adds_what_the_seven_pygame_passes_did(rim):
    """AddedLight.add with a rim (one compiled pass over the lit pixels) against its pygame
    passes (the fallback for surfaces the kernels cannot draw on): the same pixels, the
    scratch black after, on overlapping lights of several colours, one across the edge."""
    from tabletop.drawing import light as L

    def paint(k: pygame.Surface) -> pygame.Rect:
        return pygame.draw.circle(k, (200, 90, 30), (40, 50), 25).union(
            pygame.draw.circle(k, (60, 120, 240), (60, 40), 12)).union(
            pygame.draw.line(k, (255, 255, 255), (0, 90), (120, 60), 7)).union(
            pygame.draw.circle(k, (30, 250, 90), (195, 10), 15))

    ground = np.random.default_rng(1).integers(0, 256, (200, 100, 3), dtype=np.uint8)
    compiled, passes = pygame.surfarray.make_surface(ground), pygame.surfarray.make_surface(ground)
    light = L.AddedLight()
    got = light.add(compiled, paint, rim)
    old = L.AddedLight()
    scratch = old._scratch = pygame.Surface(passes.get_size(), 0, passes)
    r = paint(scratch).clip(passes.get_rect()).inflate(2 * rim + 2, 2 * rim + 2).clip(
        passes.get_rect())
    old._outline(scratch, r, rim)
    passes.blit(scratch, r, r, pygame.BLEND_RGB_ADD)
    assert got == r
    a, b = rgb(compiled).astype(int), rgb(passes).astype(int)
    assert np.abs(a - b).max() == 0 and np.abs(a - ground.transpose(1, 0, 2)).max() > 100
    assert rgb(light._scratch).max() == 0


def test_the_outline_kernel_is_warmed_as_surfaces_give_their_pixels():
    """Warmed on row-major arrays, the first hint of a run loaded a second version of the
    kernel from the cache (2 versions after a run; 33-58 ms in that frame, examples/mop.yaml)."""
    from tabletop.drawing import outline_kernel
    drawn(True)
    assert len(outline_kernel.add_outline.signatures) == 1, outline_kernel.add_outline.signatures
