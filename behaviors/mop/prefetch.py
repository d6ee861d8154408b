"""A hint to the processor, for compiled loops: fetch an array element's cache line now.

The compiled MOP passes (:mod:`behaviors.mop.window_kernel`, :mod:`behaviors.mop.group_kernel`)
read, per template, a stretch of states at an address known only from the template's progress:
one cache miss after another, the processor idle in between (DESIGN's 8 x 100 templates read
1-2 MB per tick, more than the core's own caches keep between ticks). Asking for the stretches
of the templates a few ahead lets those misses overlap the work on the current one.
"""

from __future__ import annotations

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
