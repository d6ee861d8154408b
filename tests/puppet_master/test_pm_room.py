"""The reactor's room on the table as a situation feature (features.room, Params.w_room):
batch and live agree, the demonstration's table comes from the behaviour's parameters (its
data's bounds where a file has none), and the afraid character chased by a visitor spends
no more time at the table's edges with it."""

import math

import numpy as np

from behaviors.puppet_master import features as ft
from behaviors.puppet_master import fidelity, visitors
from behaviors.puppet_master.engine import Behavior
from tabletop import examples, library
from tests.puppet_master import demos

ROOM = {"w_room": 2.0, "table_width": demos.TABLE[0], "table_height": demos.TABLE[1]}


def test_room_is_the_free_way_behind_and_to_the_sides():
    table = (0.0, 0.0, 1.2, 0.8)
    # main at the centre, reactor 0.1 m from the right edge: 0.1 m behind it, open both sides
    back, side = ft.room_at(0.6, 0.4, 1.1, 0.4, table)
    assert math.isclose(back, 0.1) and side == 0.0
    # in the top right corner, main below-left: the wall behind; to the bearing's left (up)
    # 0.05 m, to its right (down) the whole clip
    back, side = ft.room_at(0.6, 0.75, 1.15, 0.75, table)
    assert math.isclose(back, 0.05) and math.isclose(side, 0.05 - ft.ROOM_CLIP)
    assert ft.room_at(0.3, 0.3, 0.3, 0.3, table) == (ft.ROOM_CLIP, 0.0)   # on one spot


def test_live_room_equals_training_room():
    demo = demos.keep_away(3, 20.0, rate_hz=40.0)
    b = Behavior.train(demo, **ROOM)
    assert b.demo_table == (0.0, 0.0, *demos.TABLE)
    # the main's still/moving state before the room (the keep-away character keeps away from
    # its main: Behavior.scales.still), compared with the live rows on the others' columns
    still = int(b.scales.still > 0.0)
    assert still and ft.room_column(b.scales) == ft.SITUATION_DIMS + still
    assert b.situation_vectors.shape[1] == ft.SITUATION_DIMS + still + ft.ROOM_DIMS
    cols = [c for c in range(b.situation_vectors.shape[1]) if c != ft.SITUATION_DIMS]
    main, react = b.main, b.react
    p = b.params
    mm = ft.EntityMotion(*main[0], p.rate_hz, p.min_speed)
    rm = ft.EntityMotion(*react[0], p.rate_hz, p.min_speed)
    xs = np.zeros(b.situation_vectors.shape[1])
    near = 0
    for i in range(1, b.samples):
        vm, _, _ = mm.step(main[i, 0], main[i, 1])
        vr, _, _ = rm.step(react[i, 0], react[i, 1])
        fwd, left, rl = ft.relative_pose(*main[i], *react[i])
        room = ft.room_at(main[i, 0], main[i, 1], react[i, 0], react[i, 1], b.demo_table)
        near += room[0] < ft.ROOM_CLIP
        ft.situation_row(xs, b.scales, vm, vr, fwd, left, rl)
        ft.room_row(xs, b.scales, main[i, 0], main[i, 1], react[i, 0], react[i, 1],
                    b.demo_table)
        assert np.allclose(xs[cols], b.situation_vectors[i, cols], atol=1e-9)
    assert near > 0.5 * b.samples        # the walls are in the demonstration (measured 0.998)


def test_without_a_stored_table_the_data_bounds_stand_for_it():
    demo = demos.keep_away(3, 20.0, rate_hz=40.0)
    assert Behavior.train(demo, w_room=1.0).demo_table == Behavior.train(demo).bounds
    # the room off (the default): the paper's six situation features and the main's
    # still/moving state (a character that keeps away from its main)
    assert Behavior.train(demo).situation_vectors.shape[1] == ft.SITUATION_DIMS + 1


def _edge_shares(seed: int) -> dict[float, float]:
    """Time at an edge (within 0.1 m) of the shipped afraid character chased by the pursuit
    visitor of ``seed``, its edge margin off, by its room's weight (w_room 0 and 2)."""
    stored = library.load_behavior(examples.DEFAULT_OUT / "afraid")
    table = (0.0, 0.0, *examples.TABLE)
    shares = {}
    for w in (0.0, 2.0):
        # the room alone: the shipped character's edge margin (Params.edge_percentile) off
        params = {**stored.parameters, "w_room": w, "edge_percentile": 0.0}
        b = Behavior.train(stored.demonstration, **params)
        main, rows = fidelity.pursue(b, visitors.pursuer(seed, 40.0, examples.TABLE), table)
        x, y = rows[:, 1], rows[:, 2]
        edge = np.minimum.reduce([x - table[0], table[2] - x, y - table[1], table[3] - y])
        shares[w] = float(np.mean(edge < 0.1))
    return shares


def test_a_chased_afraid_character_keeps_off_the_edges_with_the_room():
    # measured: seed 2 0.73 -> 0.49, seed 5 0.65 -> 0.31 (the designer's own 0.05 and 0.05;
    # with the room counted whatever the main's distance, 0.24 and 0.24, but more open-path
    # checks lost: features.room_gate). With the main's still/moving state among its features
    # (Behavior.scales.still, a character that keeps away) 0.48 -> 0.50, 0.46 -> 0.47; with its
    # place on the live bearing beside a standing main at moments whose main stood as well
    # (StepSenses._stood_place) 0.72 -> 0.29, 0.53 -> 0.63 (over the 18 pursuits of seeds
    # 0-5, 8-13, 26-31: 0.533 -> 0.468 at an edge; 0.483 -> 0.465 before that rule)
    shares = [_edge_shares(seed) for seed in (2, 5)]
    assert max(s[0.0] for s in shares) < 0.75, shares
    assert np.mean([s[2.0] for s in shares]) < np.mean([s[0.0] for s in shares]) - 0.1, shares
