"""The point of a template's path nearest to a sample: the one projection that the path misfit
(:meth:`Refusal._judge_shape <behaviors.mop.refusal.Refusal._judge_shape>`), the follower
group's kernel (:func:`~behaviors.mop.group_kernel.update_templates`) and the overrun
(:func:`~behaviors.mop.overrun.off_path2`) measure the input against.

The path near a followed state is the segments joining the template's states within
:data:`PATH_REACH` of it (a template's last state has no segment: its point stands for one).
:func:`nearest_on_path` is inlined into each compiled caller (numba's ``inline="always"``), so
it is built with that caller's arithmetic: the group's fused multiply-adds, none elsewhere.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from behaviors.kernel_cache import compiled

#: States before and after the followed state whose joining segments make up the path the
#: input is measured against (the followed state lags or leads a fast performer by a few; the
#: refusal's and the validity's path too).
PATH_REACH = (3, 3)


@compiled(inline="always")
def nearest_on_path(means, first, last, off, g, z, v, before, after) -> float:
    """The squared distance of ``z`` (D,) from the template's path (its states ``first`` ..
    ``last``, bank index, columns ``off`` on in ``means`` (D, S)) within ``before`` and
    ``after`` states of the followed state ``g`` (bank index); ``v`` (D,): out, the nearest
    point (the first segment's of equal distances)."""
    d = z.size
    gf = int(math.floor(g))
    best_d = np.inf
    for o in range(-before, after + 1):
        j = min(max(gf + o, first), last)
        # a puck's two features: the loops over them written out (the same operations;
        # update_templates on its real arguments 605 -> 569, 624 -> 569, 588 -> 538 us
        # median, interleaved, load 22)
        if d == 2:
            ja, jb = j + off, min(j + 1, last) + off
            sa0, sa1, sb0, sb1 = means[0, ja], means[1, ja], means[0, jb], means[1, jb]
            ab0 = sb0 - sa0
            ab1 = sb1 - sa1
            za = 0.0
            ab2 = 0.0
            za += (z[0] - sa0) * ab0
            ab2 += ab0 * ab0
            za += (z[1] - sa1) * ab1
            ab2 += ab1 * ab1
            tt = min(max(za * (1.0 / max(ab2, 1e-12)), 0.0), 1.0)
            dd = 0.0
            e = (z[0] - sa0) - tt * (sb0 - sa0)
            dd += e * e
            e = (z[1] - sa1) - tt * (sb1 - sa1)
            dd += e * e
            if dd < best_d:
                best_d = dd
                v[0] = sa0 + tt * (sb0 - sa0)
                v[1] = sa1 + tt * (sb1 - sa1)
            continue
        ja = j + off
        jb = min(j + 1, last) + off   # a template's last state has no segment
        za = 0.0
        ab2 = 0.0
        for c in range(d):
            ab = means[c, jb] - means[c, ja]
            za += (z[c] - means[c, ja]) * ab
            ab2 += ab * ab
        tt = min(max(za * (1.0 / max(ab2, 1e-12)), 0.0), 1.0)
        dd = 0.0
        for c in range(d):
            e = (z[c] - means[c, ja]) - tt * (means[c, jb] - means[c, ja])
            dd += e * e
        if dd < best_d:
            best_d = dd
            for c in range(d):
                v[c] = means[c, ja] + tt * (means[c, jb] - means[c, ja])
    return best_d


_F1, _F2, _I1 = numba.float64[::1], numba.float64[:, ::1], numba.intp[::1]


@compiled(numba.void(_F2, _I1, _I1, _F2, _F1, _F2))
def nearest_on_paths(means, starts, lengths, z, g, out) -> None:
    """:func:`nearest_on_path` of every template ``k`` (states ``starts[k]`` on, ``lengths[k]``
    of them; ``means`` (D, S)) for ``z[k]`` at its followed state ``g[k]`` (bank index), within
    :data:`PATH_REACH`: the nearest points into ``out`` (K, D)."""
    for k in range(z.shape[0]):
        nearest_on_path(means, starts[k], starts[k] + lengths[k] - 1, 0, g[k], z[k], out[k],
                        PATH_REACH[0], PATH_REACH[1])
