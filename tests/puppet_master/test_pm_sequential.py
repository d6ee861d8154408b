"""Sequential training's pairing (behaviors/puppet_master/sequential.py): the reactor's samples
with the main take's pose at their times."""

import math

import numpy as np

from behaviors.puppet_master.sequential import pair_takes


def test_the_main_is_read_at_the_reactors_times_angles_through_their_turn():
    # a 60 Hz main turning through +-pi at 1 rad/s and moving at 0.2 m/s; a 30 Hz reactor
    # half a frame off it, starting before and ending after the main's playback
    t = np.arange(0.0, 5.0, 1 / 60)
    look = np.angle(np.exp(1j * (math.pi - 2.5 + t)))
    main = np.column_stack([t + 10.0, 0.1 + 0.2 * t, 0.4 + 0.0 * t, look])
    tr = np.arange(-0.5, 5.5, 1 / 30) + 1 / 120
    react = np.column_stack([tr + 10.0, 0.5 + 0.0 * tr, 0.3 + 0.0 * tr, 0.1 + 0.0 * tr])
    out = pair_takes(main, react)
    inside = tr[(tr >= 0.0) & (tr <= t[-1])]
    assert np.allclose(out[:, 0], inside - inside[0])            # times from the first kept
    assert np.allclose(out[:, 1], 0.1 + 0.2 * inside)            # interpolated, not held
    # the look interpolated along its turn (never swinging through 0 at the wrap)
    err = np.angle(np.exp(1j * (out[:, 3] - (math.pi - 2.5 + inside))))
    assert np.max(np.abs(err)) < 1e-9
    assert np.allclose(out[:, 4:], [0.5, 0.3, 0.1])
