"""Tools for MOP's compiled loops (numba): a hint to fetch memory early, and an exponential
that vectorises.

Prefetch: the compiled MOP passes (:mod:`behaviors.mop.window_kernel`,
:mod:`behaviors.mop.group_kernel`) read, per template, a stretch of states at an address known only
from the template's progress: one cache miss after another, the processor idle in between (DESIGN's
8 x 100 templates read 1-2 MB per tick, more than the core's own caches keep between ticks). Asking
for the stretches of the templates a few ahead lets those misses overlap the work on the current one
(DESIGN's tick, same process, A/B: 1.96 -> 1.47 ms CPU median on a loaded machine).

Exponential: the forward step takes about 40 000 exponentials per tick for DESIGN's case; the
library's ``exp`` is a call per value (about 5 ns), which the compiler cannot vectorise.
:func:`exp_neg` (arguments from -708 to 0: the forward's clamp is -200, the threshold model's
-708, below which the library's result is subnormal) is range reduction and a polynomial in
plain arithmetic, which it does (3.5x faster on the same loop); within 1.5 ulp of the
library's on 2 million arguments from -200 to 0 (``tests/mop/test_compiled.py``).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def prefetch(typingctx, array, index):
    """``prefetch(array, i)``: start loading the cache line of ``array[i]`` (1-D, or the first
    element of row ``i`` of a 2-D array) for reading; no effect on results, none if out of
    range (callers keep ``i`` in range anyway)."""
    sig = types.void(array, index)

    def codegen(context, builder, signature, args):
        aty = signature.args[0]
        ary = context.make_array(aty)(context, builder, args[0])
        at = [args[1]] + [context.get_constant(types.intp, 0)] * (aty.ndim - 1)
        ptr = cgutils.get_item_pointer(context, builder, aty, ary, at, wraparound=False)
        i8p, i32 = ir.IntType(8).as_pointer(), ir.IntType(32)
        fn = cgutils.get_or_insert_function(builder.module,
                                            ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
                                            "llvm.prefetch.p0i8")
        # read, high temporal locality, data cache
        builder.call(fn, [builder.bitcast(ptr, i8p), i32(0), i32(3), i32(1)])
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (``llvm.fma``; float64 or float32, all three of one type):
    what the compiler makes of ``v += a * b`` under :data:`CONTRACT`, but in an order it cannot
    choose (of a sum of products, it fuses whichever product it likes with the rest)."""
    def codegen(context, builder, signature, args):
        width = "f64" if args[0].type == ir.DoubleType() else "f32"
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(args[0].type, [args[0].type] * 3), f"llvm.fma.{width}")
        return builder.call(fn, args)
    return a(a, b, c), codegen


#: The integer of a float's width, and the LLVM type of the float (the bit casts below).
_WIDTHS = {types.float64: (types.int64, ir.DoubleType()),
           types.float32: (types.int32, ir.FloatType())}


@intrinsic
def _as_float(typingctx, bits, like):
    """The float of ``like``'s type (float64 or float32) whose bits are the low ones of the
    integer ``bits``."""
    integer, llvm = _WIDTHS[like]

    def codegen(context, builder, signature, args):
        low = builder.trunc(args[0], ir.IntType(integer.bitwidth)) \
            if bits.bitwidth > integer.bitwidth else args[0]
        return builder.bitcast(low, llvm)
    return like(bits, like), codegen


@intrinsic
def _as_bits(typingctx, value):
    """The bits of the float64 (float32) ``value`` as an int64 (int32)."""
    integer = _WIDTHS[value][0]

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(integer.bitwidth))
    return integer(value), codegen


#: numba's ``fastmath`` flags of MOP's compiled passes: a product and a sum fused into one
#: instruction (one rounding instead of two; no reordering, no assumption on infinities or NaNs).
CONTRACT = {"contract"}



_SHIFT = 6755399441055744.0           # 1.5 * 2^52: adding it rounds to an integer in the low bits
_LOG2E = 1.4426950408889634
_LN2_HI = 6.93147180369123816490e-01  # ln 2 split so that k * _LN2_HI is exact
_LN2_LO = 1.90821492927058770002e-10
_C = tuple(1.0 / math.factorial(n) for n in range(13))   # Taylor: |r| <= ln2 / 2, error < 2e-16
# the same in single precision (every constant a float32, so that no operation widens)
_F32 = np.float32
_SHIFT32, _LOG2E32 = _F32(12582912.0), _F32(_LOG2E)   # 1.5 * 2^23
_LN2_HI32, _LN2_LO32 = _F32(0.693359375), _F32(-2.12194440e-4)   # k * _LN2_HI32 exact, |k| < 2^15
_C32 = tuple(_F32(c) for c in _C[:8])   # Taylor: |r| <= ln2 / 2, error < 2e-8
_BIAS32, _MANTISSA32 = np.int32(127), np.int32(23)


@numba.njit(inline="always")
def _exp_by(x: float, log2e: float, shift: float, ln2_hi: float, ln2_lo: float, taylor: tuple,
            bias: int, mantissa: int) -> float:
    """``exp(x)`` for ``x <= 0`` down to the least normal result (no check: outside, wrong):
    ``x = k ln2 + r`` with ``k`` the nearest integer (adding ``shift``, 1.5 times the
    mantissa's range, rounds to an integer in the low bits), ``exp(r)`` by its Taylor
    polynomial (coefficients ``taylor``), ``2^k`` built in the exponent's bits (``bias``,
    ``mantissa``); every constant of ``x``'s type, so that no operation widens."""
    t = x * log2e + shift
    k = t - shift
    r = (x - k * ln2_hi) - k * ln2_lo
    top = len(taylor) - 1
    p = taylor[top]
    for j in range(top - 1, -1, -1):   # Horner
        p = p * r + taylor[j]
    return p * _as_float((_as_bits(t) + bias) << mantissa, t)


@numba.njit(inline="always")
def exp_neg(x: float) -> float:
    """``exp(x)`` for ``-708 <= x <= 0`` (:func:`_exp_by`, degree 12)."""
    return _exp_by(x, _LOG2E, _SHIFT, _LN2_HI, _LN2_LO, _C, 1023, 52)


@numba.njit(inline="always")
def exp_neg32(x: np.float32) -> np.float32:
    """:func:`exp_neg` in single precision, for float32 ``-87 <= x <= 0`` (degree 7): eight
    values to a vector where :func:`exp_neg` takes four (the threshold model's weights,
    :mod:`behaviors.mop.threshold_kernel`); within 1.2 ulp of the exact value
    (``tests/mop/test_compiled.py``)."""
    return _exp_by(x, _LOG2E32, _SHIFT32, _LN2_HI32, _LN2_LO32, _C32, _BIAS32, _MANTISSA32)
