"""States stretched along a fast stretch of their template (:mod:`behaviors.mop.stretch`): the
compiled step equals the plain equations with them, close states stay points, and the backflip
ankle's loop is followed, alone and in a group alike."""

import numpy as np
import pytest

from behaviors.mop import stretch
from behaviors.mop.forward import WindowedForward, forward_reference
from behaviors.mop.hmm import Transitions, build_bank
from behaviors.mop.stretch import state_stretches
from tests.mop.helpers import held_out_group_valid, held_out_valid


def _sparse_template(n: int = 40) -> np.ndarray:
    """A stroke out, a fast arc recorded a few samples apart, and a stroke back (metres)."""
    u = np.linspace(0.0, 1.0, n)
    speed = 1.0 + 20.0 * np.exp(-((u - 0.5) / 0.08) ** 2)   # fast in the middle: 8 sigma a state
    s = np.cumsum(speed)
    s = s / s[-1] * 2.0 * np.pi
    return np.stack([0.1 * np.sin(s), 0.05 * (1.0 - np.cos(s))], axis=1)


def test_close_states_are_points_and_far_ones_stretched_along_the_path():
    bank = build_bank({"sparse": _sparse_template()})
    tangent, half = state_stretches(bank.means, bank.starts, bank.lengths, 0.2)
    gaps = np.linalg.norm(np.diff(bank.means, axis=0), axis=1)
    near = np.minimum(gaps[:-1], gaps[1:])   # each inner state's nearer neighbour
    inner = half[1:-1]
    assert np.all(inner[near < 2.0 * stretch.STRETCH_FROM * 0.2] == 0.0)
    assert inner.max() > 0.0 and half[0] == half[-1] == 0.0
    on = half > 0
    assert np.allclose(np.linalg.norm(tangent[on], axis=1), 1.0)
    assert np.all(tangent[~on] == 0.0)


@pytest.mark.parametrize("floor", [1e-8, 0.0])
def test_the_compiled_step_with_stretched_states_equals_the_plain_equations(floor):
    rng = np.random.default_rng(3)
    tpl = _sparse_template()
    bank = build_bank({"sparse": tpl})
    spread = state_stretches(bank.means, bank.starts, bank.lengths, 0.2)
    assert spread[1].max() > 0.0
    phase = np.clip(np.cumsum(rng.uniform(0.5, 2.0, 70)), 0, len(tpl) - 1)
    x = np.array([np.interp(phase, np.arange(len(tpl)), tpl[:, c]) for c in range(2)]).T
    z = (x + rng.normal(0.0, 0.002, x.shape) - bank.center[0]) / bank.scale[0]
    transitions = Transitions(restart=1e-3)
    fw = WindowedForward(bank, sigma=0.2, half_window=15, transitions=transitions, floor=floor,
                         stretch=spread)
    got = np.array([(fw.step(s)[0], fw.mean[0]) for s in z])
    mean, _, ll, _ = forward_reference(bank.template(0), z, 0.2, 15, transitions, floor,
                                       stretch=spread)
    assert np.abs(got[:, 0] - ll).max() <= 1e-8
    assert np.abs(got[:, 1] - mean).max() <= 1e-8


def test_the_backflip_ankles_fast_loop_is_followed_as_it_is_performed():
    # held-out seed 107's backflip ankle at 0.85x: its loop moves up to 7.3 sigma a state and
    # the samples between its states read 1.8-2.3 sigma: refused in the loop. Measured: valid
    # after 30% 0.317 with point states, 0.805 stretched
    valid = held_out_valid(107, "backflip_left_ankle", 0.85)
    assert valid >= 0.7, valid


def test_a_group_follows_the_backflip_loop_as_its_follower_alone():
    # measured: 33 valid samples stretched, 13 with point states (equal to the follower alone
    # at every tick either way)
    valid = held_out_group_valid(107, "backflip_left_ankle", 0.85)
    assert valid >= 28, valid
