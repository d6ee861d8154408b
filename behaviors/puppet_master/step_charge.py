"""A demonstrated charge kept whole arriving (:class:`step.GenerationStep` calls it; the
compiled step, step_kernel, repeats it to the last bit): the live distance beyond the
demonstrated one is closed over the charge's remaining steps to the touch (at once while it
pushes), before the step's cap. Units: table metres.

Measured with bench/fidelity.py --seeds 0,1,2: 306 -> 307 of 360 (held-out seed 7: 102 -> 103);
the bully's contact met on 6 of 9 paths instead of none (0.11-0.17), its orbit lost on 3 and the
stalker and playful friend (one charge each) 2 each. Kept whole without the closing: 302
(contact 0.05-0.10); with the place held in the world during a charge: 308 but contact met on 1
of 9; target and relative step turned to the live bearing: 307, contact met on 3 of 9, orbit
lost on 3.

Where a charge falls short: a match joining it partway (live 0.30 m where the moment is at
0.19), a place held in the world capped at the demonstrated speed while the live main walks
away, and the detail turn (up to 1.3 rad at the governor's gain) of a step still fast at the
impact, which swipes it sideways 7 cm from the main. Every remedy measured (seeds 0-5 / held-out
7, against 623 / 107; bully contact met on 10 of 18 paths) trades contact for orbit, the bully's
rate round its main at close range (0.6-0.9 rad/s within 0.1 m against 0.3 demonstrated, its
faster unseen mains passing at 5 cm): cap at the top speed during a charge 586 / 101 (against
609 / 104 before the main's personal space, step_detail.py; contact 13, orbit 0 of 18); cap
raised by the live main's step away 613 / 104; the detail turning only the demonstrated length
of a charge's step 624 / 105 (contact 15, orbit 14); both 623 / 107 (contact 13, orbit 12); the
top speed only before the touch, with that detail, 622 / 107 (contact 13, orbit 14, the
still/moving ratio lost on 5); entering a charge at the moment as far from its main as the live
reactor 617 / 104. Traced again on seeds 0-5, 8-13, 26-31 x3 runs (Behavior.main_disc in place
or not): contact is short on the fast paths (mean 0.128, 14 of 54 under 0.110; the designer
0.145) and over on the slow (0.173, 7 over 0.204; the designer 0.158). On the fast paths 20-30%
of the charges never touch: a world place's cap is the moment's speed (0.26-0.43 m/s) while the
live main walks away at 0.25-0.39 (seed 0 fast, 3.1 s: all 40 steps capped, 0.325 -> 0.097 m).
Raising that cap in a charge by the live main's step away from the reactor meets the fast paths
(14 -> 1-5 low) but overshoots the slow and loops paths and orbits: bully misses 67 -> 106
(contact 34, orbit 43); at most the top speed 80 (18, 37), with the main's disc 60 (contact 3
under on the fast paths, 13 over on both others); only while farther than the moment 73; the
main's step away added after the cap 115 (orbit 62). None kept.
"""

from __future__ import annotations

import math


def close_on_touch(sx: float, sy: float, lx: float, ly: float, dist: float,
                   steps: int) -> tuple[float, float]:
    """The step (sx, sy) with the live distance to the main (``lx, ly``: main minus reactor,
    m) beyond the moment's ``dist`` (m) closed by a share of 1 / (``steps`` to the touch + 1)."""
    live = math.hypot(lx, ly)
    gap = live - dist
    if gap > 0.0 and live > 1e-9:
        gap /= max(1, steps + 1)
        sx, sy = sx + gap * lx / live, sy + gap * ly / live
    return sx, sy
