"""Features (section 4.2): batch and live agree, angles wrap, inverse-spread weights."""

import collections
import math

import numpy as np
from tests.puppet_master import demos as pm_demos

from behaviors.puppet_master import features as ft
from behaviors.puppet_master.character import STILL_MPS, STILL_SPAN_S
from behaviors.puppet_master.engine import Behavior


def _demo():
    return pm_demos.follow_behind(pm_demos.main_path(11, 20, rate_hz=40.0), wobble=0.3)


def test_live_features_equal_training_features():
    b = Behavior.train(_demo())
    main, react = b.main, b.react
    p = b.params
    # the follower stops with its main: its main's still/moving state is a feature of both
    assert b.scales.still > 0.0
    assert b.situation_vectors.shape[1] == ft.SITUATION_DIMS + 1
    assert b.coherence_vectors.shape[1] == ft.COHERENCE_DIMS + 1
    mm = ft.EntityMotion(*main[0], p.rate_hz, p.min_speed)
    rm = ft.EntityMotion(*react[0], p.rate_hz, p.min_speed)
    xs, xc = np.zeros(ft.SITUATION_DIMS + 1), np.zeros(ft.COHERENCE_DIMS + 1)
    recent = collections.deque([main[0, :2]], maxlen=int(round(STILL_SPAN_S * p.rate_hz)))
    stood = 0
    for i in range(1, b.samples):
        vm, _, _ = mm.step(main[i, 0], main[i, 1])
        vr, move_r, ddir_r = rm.step(react[i, 0], react[i, 1])
        fwd, left, rl = ft.relative_pose(*main[i], *react[i])
        ft.situation_row(xs, b.scales, vm, vr, fwd, left, rl)
        nl = math.remainder(react[i, 2] - move_r, math.tau)
        ft.coherence_row(xc, b.scales, nl, ddir_r, fwd, left, vr, vm)
        recent.append(main[i, :2])
        still = math.hypot(*(main[i, :2] - recent[0])) < STILL_MPS * STILL_SPAN_S
        stood += still
        ft.still_row(xs, b.scales, still, ft.SITUATION_DIMS)
        ft.still_row(xc, b.scales, still, ft.COHERENCE_DIMS)
        assert np.allclose(xs, b.situation_vectors[i], atol=1e-9)
        assert np.allclose(xc, b.coherence_vectors[i], atol=1e-9)
    assert 0 < stood < b.samples - 1


def test_angles_wrap_across_pi():
    rate = 40.0
    # a reactor heading west, its path wobbling across the +-pi boundary
    ang = np.array([3.1, -3.1, 3.1, -3.1, 3.1])
    pos = np.cumsum(np.column_stack([np.cos(ang), np.sin(ang)]) * 0.005, axis=0)
    main = np.column_stack([pos[:, 0] + 0.3, pos[:, 1], np.full(5, -3.13)])
    react = np.column_stack([pos, np.full(5, 3.13)])
    f = ft.pair_features(main, react, rate, 0.01)
    assert np.all(np.abs(f.ddir_react[2:]) < 0.2)      # 0.083 rad turns, not 2 pi - 0.083
    assert np.all(np.abs(f.rel_look - (-math.tau + 6.26)) < 1e-9)  # 3.13 - (-3.13) wraps to -0.023
    assert np.all(np.abs(f.norm_look_react[1:]) < 0.1)
    assert np.all((f.move_react > -math.pi) & (f.move_react <= math.pi))


def test_a_still_entity_keeps_its_movement_direction():
    pos = np.array([[0, 0], [0.01, 0], [0.01, 0.00001], [0.01, 0], [0.01, 0.01]], float)
    speed, move, ddir = ft.movement(pos, np.zeros(5), 40.0, 0.01)
    assert move[2] == move[3] == 0.0          # jitter of 0.4 mm/s has no direction
    assert abs(move[4] - math.pi / 2) < 1e-12 and abs(ddir[4] - math.pi / 2) < 1e-12


def test_no_unit_dominates_the_weighted_features():
    # the same demonstration in centimetres gives the same weighted vectors (the paper's;
    # the main's still/moving state is a flag read at a still speed in table metres)
    demo = _demo()
    cm = demo.copy()
    cm[:, [1, 2, 4, 5]] *= 100.0
    b_m = Behavior.train(demo)
    b_cm = Behavior.train(cm, min_speed=1.0)
    paper_s, paper_c = slice(0, ft.SITUATION_DIMS), slice(0, ft.COHERENCE_DIMS)
    assert np.allclose(b_m.situation_vectors[:, paper_s], b_cm.situation_vectors[:, paper_s],
                       atol=1e-6)
    assert np.allclose(b_m.coherence_vectors[:, paper_c], b_cm.coherence_vectors[:, paper_c],
                       atol=1e-6)
    # and every weighted feature has a spread near 1 (angles: embedded, per component pair)
    sv = b_m.situation_vectors
    assert 0.5 < np.std(sv[:, 0]) < 1.5 and 0.5 < np.std(sv[:, 1]) < 1.5
    assert 0.5 < math.sqrt(np.var(sv[:, 2]) + np.var(sv[:, 3])) < 1.5
