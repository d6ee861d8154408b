"""A face's early feedback (MOP): the suspected expression shows faintly on the face itself. A
faint face drawn before the face lay wholly under it, opaque, and was never seen. Real pygame
surfaces, the MOP example's face model."""

import math

import numpy as np
import pygame
import pytest

from behaviors.mop.creatures import FaceModel
from behaviors.motion.skeleton import place
from tabletop.frames import CharacterState, Frame
from tabletop.view import Renderer

from tests.tabletop.test_view import SIZE, TABLE, rgb

pytestmark = pytest.mark.usefixtures("pygame_display")

MODEL = FaceModel()


def face(hint: bool) -> CharacterState:
    """The face resting at the table's middle; hinted, its suspected expression opens the jaw
    (its mouth 0.12 face heights lower)."""
    rest = place(MODEL.neutral, 0.6, 0.4, math.pi / 2, 0.22)
    jaw = MODEL.neutral + MODEL.deltas[MODEL.BLENDSHAPES.index("jaw_open")]
    extra = dict(hints=(("laugh", 0.9, 0.4),),
                 hint_points=place(jaw, 0.6, 0.4, math.pi / 2, 0.22)) if hint else {}
    return CharacterState("face", 0.6, 0.4, math.pi / 2, kind="face", size=0.22, points=rest,
                          bones=MODEL.bones, color=(120, 180, 255), valid=False, **extra)


def drawn(hint: bool) -> tuple[np.ndarray, Renderer]:
    r = Renderer(TABLE, SIZE)
    s = pygame.Surface(SIZE)
    # a second: the hint faded in; drawn every 0.1 s (the last image is the one every 30 Hz
    # frame makes, to the pixel)
    for k in (*range(0, 29, 3), 29):
        r.draw(s, Frame(seq=k, t=1.0 + k / 30, characters=(face(hint),)))
    return rgb(s).astype(int).sum(axis=2), r


def test_a_faces_suspected_expression_shows_faintly_on_it():
    plain, r = drawn(False)
    hinted, _ = drawn(True)
    c = face(True)
    head = r.map.points(c.points[MODEL.part_slices["outline"]])
    mask = pygame.Surface(SIZE)
    centre = head.mean(axis=0)
    pygame.draw.polygon(mask, (255, 255, 255), ((head - centre) * 0.9 + centre).tolist())
    inside = pygame.surfarray.array_red(mask).T > 0        # well inside the head
    darker = (plain - hinted) * inside
    # measured before: nothing (0 pixels darker by 40 or more); now 1249: the faint open mouth
    assert (darker >= 40).sum() > 150
    ink = plain[inside].min()                             # the face's own mouth, brows, pupils
    skin = np.median(plain[inside])
    faint = hinted[(darker >= 40) & (np.abs(plain - skin) <= 6)]   # over bare skin
    # faint: far lighter than its ink (measured: ink 66, skin 511, the hinted mouth >= 306)
    assert len(faint) > 150 and faint.min() > ink + 120
    # the face's own features stay whole: where it has ink, it still has
    assert (hinted[inside & (plain <= ink + 20)] <= ink + 20).all()


def test_a_hybrids_suspected_expression_shows_on_its_face():
    """The gecko (MOP section 3's hybrid): a suspected laugh shows faintly on its face too."""
    from dataclasses import replace

    from behaviors.mop.creatures import hybrid_clips
    from tests.tabletop.test_view_mop import gecko
    c, rig = gecko(0.0, 0.0)
    laugh = place(rig.pose(hybrid_clips()["wag_laugh"], 0.5), 0.6, 0.4, 0.0, 0.25)
    laugh[:len(rig.body.rest())] = c.points[:len(rig.body.rest())]   # the same body: the face
    imgs = []
    for hinted in (False, True):
        s = replace(c, valid=False, **(dict(hints=(("zigzag", 0.9, 0.5),), hint_points=laugh)
                                      if hinted else {}))
        r = Renderer(TABLE, SIZE)
        surf = pygame.Surface(SIZE)
        for k in range(30):
            r.draw(surf, Frame(seq=k, t=1.0 + k / 30, characters=(s,)))
        imgs.append(rgb(surf).astype(int).sum(axis=2))
    k = len(rig.body.rest())
    head = r.map.points(c.points[k:][MODEL.part_slices["outline"]])
    mask = pygame.Surface(SIZE)
    centre = head.mean(axis=0)
    pygame.draw.polygon(mask, (255, 255, 255), ((head - centre) * 0.9 + centre).tolist())
    inside = pygame.surfarray.array_red(mask).T > 0
    darker = (imgs[0] - imgs[1]) * inside
    # measured before: 0 pixels of its face darker by 40 or more; now 183: the faint laugh
    assert (darker >= 40).sum() > 20
