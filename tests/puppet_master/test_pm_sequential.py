"""Sequential training's pairing (behaviors/puppet_master/sequential.py): the reactor's samples
with the main take's pose at their times."""

import math

import numpy as np

import pytest

from behaviors.puppet_master.sequential import TakeError, left_out, pair_takes


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


def test_takes_timed_in_other_units_are_refused_naming_both_spacings():
    # a reactor take in milliseconds against a main in seconds paired its first 4 samples
    # into a 75 s demonstration; the other way round, the whole reaction with the main's
    # first 80 ms: both trained without a word
    t = np.arange(0.0, 80.0, 0.025)
    main = np.column_stack([t, 0.1 + 0.005 * t, 0.4 + 0.0 * t, 0.0 * t])
    react = np.column_stack([t, 0.5 + 0.0 * t, 0.3 + 0.0 * t, 0.1 + 0.0 * t])
    for m, r in ((main, react * [1000.0, 1, 1, 1]), (main * [1000.0, 1, 1, 1], react)):
        with pytest.raises(TakeError, match=r"0\.025 s.*25 s|25 s.*0\.025 s") as exc:
            pair_takes(m, r)
        assert "milliseconds given for one?" in str(exc.value)
    # 30 Hz against 120 Hz are two rates: paired
    assert pair_takes(main, react[::4]).shape == (800, 7)


def test_what_pairing_leaves_out_is_said_from_a_twentieth_of_the_reaction():
    t = np.arange(0.0, 10.0, 0.025)
    main = np.column_stack([t, 0.1 + 0.02 * t, 0.4 + 0.0 * t, 0.0 * t])
    react = np.column_stack([t, 0.5 + 0.0 * t, 0.3 + 0.0 * t, 0.1 + 0.0 * t])
    assert left_out(main, react) == ""
    assert left_out(main, react + [0.45, 0, 0, 0]) == ""           # 18 of 400 beyond the end
    said = left_out(main, react + [0.5, 0, 0, 0])                   # 20 of 400
    assert said.startswith("20 of 400 reactor samples (0.5..10.475 s) lie outside the main "
                           "take's playback (0..9.975 s)")
