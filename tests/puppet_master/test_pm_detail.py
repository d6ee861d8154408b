"""Detail incorporation (4.4.2): four-level Haar high-pass and fixed 16-step patches."""


import numpy as np
import pywt

from behaviors.puppet_master.detail import DetailPatch, haar_detail


def high_frequency_ratio(signal: np.ndarray, levels: int = 4) -> float:
    """Energy share (0..1) of ``signal``'s detail part above fs / 2**levels."""
    x = np.asarray(signal, dtype=float)
    x = x - x.mean()
    total = float(np.dot(x, x))
    if total <= 0.0:
        return 0.0
    h = haar_detail(x, levels)
    return float(np.dot(h, h)) / total


def test_haar_detail_keeps_fast_texture_and_drops_the_trend():
    i = np.arange(1024)
    slow = np.sin(2 * np.pi * i / 512.0)       # fs/512, far below the fs/16 cut
    fast = 0.2 * np.sin(2 * np.pi * i / 6.0)   # fs/6, above it
    h = haar_detail(slow + fast, 4)
    # Haar is a coarse filter (16-sample blocks of a 6-sample period do not average to zero):
    # measured 0.30 of the texture's RMS here
    assert np.sqrt(np.mean((h - fast) ** 2)) < 0.4 * np.sqrt(np.mean(fast ** 2))
    assert high_frequency_ratio(slow) < 0.01
    assert high_frequency_ratio(np.sin(2 * np.pi * i / 256.0)) < 0.02
    assert high_frequency_ratio(fast) > 0.95
    assert high_frequency_ratio(np.sin(2 * np.pi * i / 16.0 + 0.3)) > 0.95


def test_a_steady_turn_has_no_texture():
    # a character turning at 2.5 rad/s sampled at 40 Hz: a ramp of direction, no wobble
    ramp = np.arange(400) * 2.5 / 40.0
    assert np.max(np.abs(haar_detail(ramp, 4))) < 1e-9
    # the decimated transform would leave a sawtooth of about slope x 8 here
    coeffs = pywt.wavedec(ramp, "haar", mode="periodization", level=4)
    coeffs[0][:] = 0.0
    saw = pywt.waverec(coeffs, "haar", mode="periodization")[:400]
    assert np.max(np.abs(saw[20:-20])) > 0.3


def test_detail_is_shift_invariant():
    x = np.random.default_rng(3).normal(size=400).cumsum() * 0.05
    a = haar_detail(x, 4)
    b = haar_detail(x[5:], 4)
    assert np.allclose(a[5 + 40:-40], b[40:-40], atol=1e-9)


def test_a_patch_keeps_its_source_for_sixteen_steps():
    detail = np.arange(1000, dtype=float) / 1000.0
    p = DetailPatch(detail, 16)
    got = [p.next(source) for source in range(100, 140)]   # the match moves every step
    assert got[:16] == [100 + k for k in range(16)]
    assert got[16:32] == [116 + k for k in range(16)]
    assert got[32] == 132
    assert DetailPatch(detail, 16).next(5000) == -1        # past the end: no detail
    assert all(0 <= i < detail.size for i in got)
