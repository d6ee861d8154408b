"""The generation step's scalar arithmetic compiled as CPython computes it, to the last bit:
``math.remainder`` (with it tabletop.frames.wrap_angle), ``math.hypot`` (CPython 3.11's, not
libm's), and Python's ``min`` / ``max`` argument order. The compiled step (step_kernel) and
its generation functions (generation_kernel) compute with these, so that they give the
Python step's poses bit for bit (tests/puppet_master/test_pm_step_kernel.py).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled

_f8 = numba.float64


@compiled(_f8(_f8, _f8))
def remainder(x: float, y: float) -> float:
    """math.remainder(x, y) for finite x and y > 0, as CPython computes it (exact)."""
    absx, absy = abs(x), abs(y)
    m = np.fmod(absx, absy)
    c = absy - m
    if m < c:
        r = m
    elif m > c:
        r = -c
    else:
        r = m - 2.0 * np.fmod(0.5 * (absx - m), absy)
    return math.copysign(1.0, x) * r


@compiled(_f8(_f8, _f8))
def hypot(a: float, b: float) -> float:
    """math.hypot(a, b) as CPython 3.11 computes it (vector_norm: scaled by a power of two,
    exact squares by Veltkamp splitting, compensated sums and one correction of the root);
    libm's hypot differs from it in the last bit now and then."""
    x0, x1 = abs(a), abs(b)
    mx = x0 if x0 > x1 else x1
    if math.isinf(mx):
        return mx
    if math.isnan(a) or math.isnan(b):
        return math.nan
    if mx == 0.0:
        return mx
    _, max_e = math.frexp(mx)
    if max_e < -1023:                      # subnormal: not met at table scale
        return math.sqrt(a * a + b * b)
    scale = math.ldexp(1.0, -max_e)
    t27 = 134217729.0
    csum, frac1, frac2, frac3 = 1.0, 0.0, 0.0, 0.0
    for i in range(2):
        x = (x0 if i == 0 else x1) * scale
        t = x * t27
        hi = t - (t - x)
        lo = x - hi
        x = hi * hi
        old = csum
        csum += x
        frac1 += (old - csum) + x
        x = 2.0 * hi * lo
        old = csum
        csum += x
        frac2 += (old - csum) + x
        frac3 += lo * lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2 + frac3))
    t = h * t27
    hi = t - (t - h)
    lo = h - hi
    x = -hi * hi
    old = csum
    csum += x
    frac1 += (old - csum) + x
    x = -2.0 * hi * lo
    old = csum
    csum += x
    frac2 += (old - csum) + x
    x = -lo * lo
    old = csum
    csum += x
    frac3 += (old - csum) + x
    x = csum - 1.0 + (frac1 + frac2 + frac3)
    return (h + x / (2.0 * h)) / scale


@compiled(_f8(_f8))
def wrap_angle(a: float) -> float:
    """tabletop.frames.wrap_angle."""
    w = remainder(a, math.tau)
    return math.pi if w == -math.pi else w


@compiled(_f8(_f8, _f8))
def _max(a: float, b: float) -> float:
    """Python's max(a, b): a unless b is greater."""
    return b if b > a else a


@compiled(_f8(_f8, _f8))
def _min(a: float, b: float) -> float:
    """Python's min(a, b): a unless b is less."""
    return b if b < a else a

