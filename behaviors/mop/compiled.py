"""Tools for MOP's compiled loops (numba): a hint to fetch memory early, and an exponential
that vectorises.

Prefetch: the compiled MOP passes (:mod:`behaviors.mop.window_kernel`, :mod:`behaviors.mop.group_kernel`)
read, per template, a stretch of states at an address known only from the template's progress:
one cache miss after another, the processor idle in between (DESIGN's 8 x 100 templates read
1-2 MB per tick, more than the core's own caches keep between ticks). Asking for the stretches
of the templates a few ahead lets those misses overlap the work on the current one (DESIGN's
tick, same process, A/B: 1.96 -> 1.47 ms CPU median on a loaded machine).

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
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
                                            "llvm.prefetch.p0i8")
        # read, high temporal locality, data cache
        builder.call(fn, [builder.bitcast(ptr, i8p), i32(0), i32(3), i32(1)])
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _as_float(typingctx, bits):
    """The float64 whose bits are the int64 ``bits``."""
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())
    return types.float64(types.int64), codegen


@intrinsic
def _as_bits(typingctx, value):
    """The bits of the float64 ``value`` as an int64."""
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))
    return types.int64(types.float64), codegen


#: numba's ``fastmath`` flags of MOP's compiled passes: a product and a sum fused into one
#: instruction (one rounding instead of two; no reordering, no assumption on infinities or NaNs).
CONTRACT = {"contract"}

_SHIFT = 6755399441055744.0           # 1.5 * 2^52: adding it rounds to an integer in the low bits
_LOG2E = 1.4426950408889634
_LN2_HI = 6.93147180369123816490e-01  # ln 2 split so that k * _LN2_HI is exact
_LN2_LO = 1.90821492927058770002e-10
_C = tuple(1.0 / math.factorial(n) for n in range(13))   # Taylor: |r| <= ln2 / 2, error < 2e-16


@numba.njit(inline="always")
def exp_neg(x: float) -> float:
    """``exp(x)`` for ``-708 <= x <= 0`` (no check: outside, wrong): ``x = k ln2 + r`` with
    ``k`` the nearest integer, ``exp(r)`` by its Taylor polynomial (degree 12), ``2^k`` built
    in the exponent's bits."""
    t = x * _LOG2E + _SHIFT
    k = t - _SHIFT
    r = (x - k * _LN2_HI) - k * _LN2_LO
    p = _C[12]
    for j in range(11, -1, -1):   # Horner
        p = p * r + _C[j]
    return p * _as_float((_as_bits(t) + 1023) << 52)
