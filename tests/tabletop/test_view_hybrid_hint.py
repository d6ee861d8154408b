"""A hybrid's early feedback (MOP): the suspected pose's face features show on the live face
where that face's own features are, though the suspected body stands elsewhere (the mime's
suspected jump lifts its head 2 cm, 17 px at 1280x720: its faint brows, nose and mouth lay
beside the live ones, a second face smudged over the first). Real pygame surfaces, the
example's mime."""

import math
from dataclasses import replace

import numpy as np
import pygame
import pytest

from behaviors.mop.creatures import FaceModel
from tabletop.frames import Frame
from tabletop.view import Renderer

from tests.tabletop.test_view import SIZE, TABLE, rgb
from tests.tabletop.test_view_mop import mime

pytestmark = pytest.mark.usefixtures("pygame_display")

MODEL = FaceModel()


def moved(xy: np.ndarray, turn: float, shift: tuple[float, float]) -> np.ndarray:
    """``xy`` (table metres) turned by ``turn`` radians about its lowest point and shifted."""
    pivot = xy[np.argmin(xy[:, 1])]
    c, s = math.cos(turn), math.sin(turn)
    return (xy - pivot) @ np.array([[c, s], [-s, c]]) + pivot + np.asarray(shift)


@pytest.mark.parametrize("turn, shift", [(0.0, (0.0, 0.02)), (0.08, (0.0, 0.0))])
def test_a_hybrids_suspected_face_lies_on_its_live_face(turn, shift):
    """The same expression suspected on a body lifted (a jump) or leaning: nothing new to
    show, so the face looks as it does unhinted, not doubled."""
    c, k = mime("talk")
    hinted = replace(c, valid=False, hints=(("zigzag", 0.9, 0.5),),
                     hint_points=moved(np.asarray(c.points), turn, shift))
    imgs = []
    for s in (replace(c, valid=False), hinted):
        r = Renderer(TABLE, SIZE)
        surf = pygame.Surface(SIZE)
        for j in range(30):       # a second: the hint faded in
            r.draw(surf, Frame(seq=j, t=1.0 + j / 30, characters=(s,)))
        imgs.append(rgb(surf).sum(axis=2))
    head = r.map.points(np.asarray(c.points)[k:][MODEL.part_slices["outline"]])
    mask = pygame.Surface(SIZE)
    centre = head.mean(axis=0)
    pygame.draw.polygon(mask, (255, 255, 255), ((head - centre) * 0.9 + centre).tolist())
    inside = pygame.surfarray.array_red(mask).T > 0        # well inside the live face
    darker = (imgs[0] - imgs[1]) * inside
    skin = np.abs(imgs[0] - np.median(imgs[0][inside])) <= 6         # bare skin, unhinted
    # measured (RGB sums): before, 170 and 149 px of bare skin darker by 40 or more (the faint
    # features beside the face's own), up to 212 darker; now none, and only the edges of its
    # own features a little darker (the faint ones under them), by 54 at most
    assert ((darker >= 40) & skin).sum() <= 5
    assert darker.max() < 100
