"""A figure's glow lies under its body: a humanoid posed with one arm stretched out (as a
visitor drags a touch-posed hand) keeps its light about its points, not about their bounding
box, which the arm pulls out over the empty table. Real pygame surfaces, offscreen."""

import numpy as np
import pygame
import pytest

from tabletop.drawing.characters import Pose, draw_figure
from tabletop.frames import CharacterState
from tabletop.table_map import TableToScreen

TABLE_RGB = (24, 29, 44)
# pelvis, chest, neck, head; two legs; an arm hanging; an arm stretched out to the right
POINTS = np.array([[0.6, 0.30], [0.6, 0.40], [0.6, 0.45], [0.6, 0.50],
                   [0.58, 0.22], [0.57, 0.15], [0.62, 0.22], [0.63, 0.15],
                   [0.58, 0.40], [0.57, 0.33], [0.72, 0.46], [0.86, 0.47]])
BONES = ((0, 1), (1, 2), (2, 3), (0, 4), (4, 5), (0, 6), (6, 7), (1, 8), (8, 9), (1, 10),
         (10, 11))


pytestmark = pytest.mark.usefixtures("pygame_display")


def test_a_figure_with_an_arm_stretched_out_keeps_its_glow_under_its_body():
    """The glow's light (the figure drawn with and without it) has its centroid within 25 px
    of the mean of the figure's points (the torso is 23 px left of it); about the points'
    bounding box it was 80 px off, over the empty table beside the body."""
    m = TableToScreen((1.2, 0.8), (1280, 720), 24)
    c = CharacterState("poser", 0.6, 0.3, 1.57, kind="skeleton", size=0.4, points=POINTS,
                       bones=BONES, color=(120, 220, 255))

    def image(light):
        s = pygame.Surface((1280, 720))
        s.fill(TABLE_RGB)
        draw_figure(s, c, Pose(m.point(0.6, 0.3), -1.57, m.scale_at(0.6, 0.3), light=light),
                    POINTS, m.H)
        return pygame.surfarray.array3d(s).transpose(1, 0, 2).astype(float)

    light = np.clip((image(1.0) - image(0.0)).sum(axis=2), 0.0, None)
    assert light.sum() > 1e5                               # it has a glow
    yy, xx = np.mgrid[0:720, 0:1280]
    centroid = np.array([(xx * light).sum(), (yy * light).sum()]) / light.sum()
    mean = m.points(POINTS).mean(axis=0)
    assert np.hypot(*(centroid - mean)) < 25.0, (centroid, mean)
