"""Detail incorporation (4.4.2): four-level Haar high-pass and fixed 16-step patches."""

import math

import numpy as np
import pywt

from behaviors.puppet_master.detail import DetailPatch, haar_detail, high_frequency_ratio


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


def test_detail_plus_approximation_recomposes_the_signal():
    x = np.random.default_rng(3).normal(size=333).cumsum()
    h = haar_detail(x, 4)
    coeffs = pywt.wavedec(x, "haar", mode="periodization", level=4)
    low = pywt.waverec([coeffs[0]] + [np.zeros_like(c) for c in coeffs[1:]], "haar",
                       mode="periodization")
    m = min(low.size, x.size)
    assert np.allclose(h[:m] + low[:m], x[:m], atol=1e-10)


def test_a_patch_keeps_its_source_for_sixteen_steps():
    detail = np.arange(1000, dtype=float) / 1000.0
    p = DetailPatch(detail, 16)
    got = [p.next(source) for source in range(100, 140)]   # the match moves every step
    assert got[:16] == [detail[100 + k] for k in range(16)]
    assert got[16:32] == [detail[116 + k] for k in range(16)]
    assert got[32] == detail[132]
    assert DetailPatch(detail, 16).next(5000) == 0.0
    assert math.isfinite(got[-1])
