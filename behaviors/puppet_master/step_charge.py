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
main's step away added after the cap 115 (orbit 62). None kept. Its fast contact misses recur
on the same paths (seeds 43, 44 fast in each of seven runs, relative_motion x 1, 1 +- 0.001 to
0.003). That cap raised only by the live main's step away beyond the moment's main's (none where
the moment's main came nearer), Python step, the bully's misses (the engine's) over those seven
runs on seeds 0-5 / 40-51 / 128-139, against 20 / 35 / 27: 15 / 35 / 24, its fast contact misses
28 -> 6 (mean 0.132 -> 0.148-0.165, shown 0.157) and orbit 21 -> 12, but loops and slow contact
over (4 -> 13; loops 0.150-0.156 -> 0.167-0.174) and its still/moving ratio lower (0.90-1.04 ->
0.84-0.97; misses 29 -> 42); half of it 19 / 35 / 27; only while farther than the moment 11 / 40
/ 27; only while the live main walks away at 0.25 m/s or more 22 / 28 / 30. Only while the
live main walks straight (its walking direction over two 0.25 s spans, as the situation's turn,
turned under 0.3 rad, each span walked at 0.05 / 0.15 m/s or more): 22 / 24 / 40 and 18 / 35
/ 33; contact misses 32 -> 16 / 9 (loops contact 4 -> 1 / 0, fast 28 -> 15 / 8), but still/moving
29 -> 48 / 48 (the charges arrive before the main stands: the bully's speed beside its still
main 0.27 -> 0.15 m/s on seeds 4 slow, 5 fast, 43 fast, 131 slow) and orbit 21 -> 22 / 28
(loops 4 -> 8 / 12). The cap raised instead by the closing share of the live distance beyond
the moment's (what close_on_touch adds): 36 / 71 / 65, contact over on every kind (49), orbit
75. Not kept: the contact a raise restores is paid in the still/moving ratio.

Where a charge goes round its main. Within 0.1 m the bully goes round it at 0.74-0.93 rad/s (slow
paths of seeds 41, 134, 135, 302, 306; its designer 0.20-0.35), in charges, from the drift
correction toward a place held in the live main's frame, which turns and moves with the live main:
the replayed segment chases a moving point. The bully's misses (the engine's alone) on seeds 0-5 /
40-51 / 128-139 / 300-311, three runs (relative_motion x 1, 1 + 0.001, 1 - 0.001; Python step): as
here 0 (0) / 6 (5) / 5 (4) / 9 (6), 1 (1) / 4 (4) / 5 (3) / 9 (7), 2 (2) / 5 (4) / 8 (6) / 10 (6),
over the three 64 (48): orbit 28 (21), still/moving 21 (12), contact 15 (15). Within 0.12 m, at
main-frame places in a charge after the cap, the step's part round the main held to the matched
moment's own rate round it (its world bearing's change averaged over 1 s), the step's length kept
(the held part turned along the bearing): 2 (2) / 2 (2) / 5 (4) / 4 (3), 1 (1) / 4 (3) / 3 (2) / 3
(1), 1 (1) / 4 (3) / 5 (4) / 3 (1), 37 (27): orbit 4 (1), still/moving 19 (12), contact 14 (14),
slow-path orbit mean 0.296-0.305 -> 0.263-0.270 rad/s (0.275 shown); but seeds 0-5 4 against 3
(bench/fidelity.py --seeds 0,1,2,3,4,5 677 (7) -> 675 (9): seed 4 slow's contact 0.211 over 0.204),
and its contact episodes on the slow and fast paths of seeds 0-5 off its designer's by 1.58 a path
against 0.92 (tests/puppet_master/test_pm_push_rhythm.py: 1.3 at most); the held part turned inward
only (an outward step only held) 43 (31), contact 18 (18), episodes off by 1.25. Within 0.1 / 0.15
m 40 (27) / 52 (35); held without its length 62 (43), contact 22 (22). Held at every distance 50
(33), orbit 1, but still/moving 37 (20) (a held charge walked slower beside a walking main: 0.306
-> 0.263 m/s on seed 5 slow); with the rate read one sample later (demonstrated.angle_rates) 66
(47), at its length then 46 (37), still/moving 32 (25), that only while the live main walks 58
(43). Held at every distance, one run each (against 20 (15)): over 0.5 s / 2 s 17 (15) / 19 (14),
at world places too 21 (17), the step less the main's held 27 (16), within the live main's turn +-
the moment's rate in its frame 55 (30) (orbit 38). The demonstrated charge turned about the main
once at its entry to the live bearing (the place alone / with its relative step) 31 (19) / 33 (23)
(the fast paths' orbit 0.294 -> 0.325-0.333); a kept charge ended where the live rate over 0.25 s
passed 1.5 x the moment's 47 (39), contact 35 (in charges on 9-13% of steps against 25%). None
kept.

The same hold within 0.12 m only while the live main's pace over its last positions (main_recent,
0.5 s) is no more than the matched moment's main's over 0.5 s (so a fast main is still pushed as
often: the rhythm the hold lost there), summed over the three runs as above per set: 11 (8) / 11
(9) / 17 (12) / 20 (15), 59 (44) against 64 (48), but seeds 0-5 3 -> 11: the slow paths'
still/moving (seeds 2, 4, 5: 7 of the 11). Not kept.

The still side: a stand given its charge back. The demonstrated bully charges its standing main
2.7 times as often as its walking one (4 of its 15 charges start or touch where its main stood,
12% of the samples). Its misses (the engine's alone) over the seven runs per set above, against
20 / 35 / 27 = 82 (contact 32, orbit 21, still/moving 29): the main's still/moving state
(features.main_still) in its situation and coherence vectors at 1 / 0.5 / 0.25 x its inverse
spread 16 / 48 / 59, 17 / 35 / 22 (contact 20, orbit 15, still/moving 39), 11 / 16 / 44
(still/moving 34; 128-139's 9 -> 23, over and under); each with the raise above 21 / 39 / 48,
26 / 52 / 36 (fast contact over), 23 / 19 / 39. The live steps since the last push counted
x 2 / 1.5 / 1.25 while the live main stands (its lurk shortened in a stand): 11 / 22 / 36 = 69
(contact 28, orbit 15, still/moving 26; 128-139 4-8 a run against 2-6), 24 / 20 / 20 = 64
(contact 10, orbit 16, still/moving 38: seeds 1 slow over, 5 fast under), 23 / 33 / 43 = 99
(still/moving 52); x 2 with the raise 29 / 41 / 38. None kept: each re-draws which paths miss
(not monotone in the factor; a per-run total of 8-12 against 8-16 at x 2), and with the raise
every one is worse than without it. Both rules together (the state at 0.25, the count x 1.5 / x 2):
11 / 29 / 23 = 63 (contact 12, still/moving 24, but orbit 27: fast paths 3 -> 12 over), 13 / 33
/ 23 = 69 (contact 18, still/moving 25, orbit 26: 40-51 slow 6 -> 17). Not kept: orbit worse.

What those rules' orbit is (Python step, the fast paths of seeds 3, 47, 51, 130, eight runs, the
state at 0.25 and the count x 1.5): orbit 0.311 -> 0.419 rad/s, 0.078 of the rise in kept
charges, 0.067 at main-frame places at the pucks' touch (0.049 m; 34 -> 52 such steps a run).
Seed 130 fast, 18.4-19.2 s: in the run-up, carried with a main walking across its bearing (0.15-
0.3 m/s, turning 1.74 rad in 0.55 s, the moments' main 1.33), the bully falls round it at 0.6-2.6
rad/s the other way from the moments (world bearing -0.8 rad, theirs +0.8); at the touch its place
lies 2-2.8 rad round the main and, held out by the main's disc, it goes round at 3-11 rad/s (0.15-
0.55 m/s across the bearing, the main 0.02-0.13 m/s). The rules time more charges into such runs.
On the loops and slow paths (seeds 48, 49 loops, 42 slow; the count x 1.86) more charges beside a
walking main (372 -> 425 charge steps a run, orbit in them 0.094 -> 0.143): the charges' own
orbit near the main, taken more often. The count's factor read from the demonstration (charges
begun a second of its main's stands over a second of its walk: 3 of 15 in 12% of the samples,
1.86), with the state at 0.25: 11 / 35 / 14 = 60 (contact 17, orbit 23, still/moving 19, speed
1). Remedies at that cause, seven runs per set as above against 82: the live main's turn beyond
the moment's main's left out of a charge's main-frame place (with both rules at 0.25 / x 1.5) 20
/ 43 / 56 (orbit 80); the push, from the touch, at the moment's distance on the live bearing 18
and 21 against 11 on seeds 0-5 alone (loops orbit 6, 13), not run further. Within 0.12 m of its main
a kept charge's step after the cap, at main-frame places, with its part round the main held to the
moment's own rate round it (its world bearing over 1 s centred) and its length kept along the
bearing: alone 9 / 22 / 32 = 63 (contact 30, orbit 2, still/moving 31; a run 8-11 against 8-16;
orbit mean 0.29-0.31 -> 0.27-0.28 rad/s, speed beside a still or walking main within 0.01 m/s), its
part round the main less the live main's step held instead 26 / 40 on the first two sets (loops
orbit 17); held to the moment's own orbit rate instead (its step's part round its main over its
distance, over 1 s, as bench/fidelity.py's figure) 11 / 32 / 30 = 73 (contact 46: the fast paths
under), with the count x 1.86 12 / 19 / 29 = 60 (contact 24, orbit 5, still/moving 31; push rhythm
off by 1.42); the bearing's hold with the count x 1.86 14 / 14 / 25 = 53 (contact 14, orbit 5,
still/moving 34: 128-139 9 -> 18; a run 4-9), also with the state at 0.25 15 / 14 / 32 (contact 35),
at 0.25 and x 1.5 18 / 30 / 30, with the state at 0.25 alone 8 / 10 / 38 (still/moving 37: 128-139
29), at 0.125 and x 1.86 10 / 22 / 15 = 47 (contact 23, orbit 11, still/moving 13; a run 3-9) but
bench/fidelity.py 676 (the engine's alone 5 -> 8) and push rhythm off by 1.33. bench/fidelity.py
--seeds 0,1,2,3,4,5: 679 -> 677 (the hold alone: the bully's still/moving on seeds 3, 5 slow) and
677 with x 1.86 (seed 2 fast contact, 3 slow still/moving); with x 1.86 the bully's contact episodes
on the slow and fast paths of seeds 0-5 are off its designer's by 1.42 a path
(tests/puppet_master/test_pm_push_rhythm.py: 1.3 at most; the hold alone 1.0). None kept: each moves
the still/moving misses onto other paths (the per-path ratio sits at the band's edges, 0.68-1.26),
and the hold's gain in orbit is paid there; the hold with the state at 0.125 and the count x 1.86,
the one with every set and figure lower, misses the push rhythm (1.33) and the bench (676).
The state's weight between, with the hold and x 1.86: at 0.1375 / 0.15 / 0.1625 / 0.175 / 0.2
54 / 32 / 56 / 57 / 68 (still/moving 33 / 21 / 34 / 25 / 34); without the count, at 0.15 /
0.175 / 0.2, 68 / 72 / 57 (still/moving 36-40). At 0.15: 9 / 12 / 11 (contact 11, orbit 0; a
run 2-6 against 8-16), push rhythm off by 1.08 (fast -0.83), but seeds 0-5's still/moving 7 -> 9
and bench/fidelity.py 677 (the bully's still/moving on seeds 1 slow, 3 loops). Not kept: a dip
its neighbours (54, 56) do not share, and the bench's still/moving lost.

Where the bully's misses are its engine's (bench/fidelity.py's figures on seeds 0-5, 40-45,
300-305; the engine's alone 0 / 5 / 3): on those 18 paths of each kind it misses its slow
orbit on 3 (its designer on none; 0.380-0.397 over the band's 0.375, mean 0.298 against 0.275
shown, its designer's 0.241) and its fast contact on 2 (none; 0.089 / 0.100, mean 0.137 against
0.157, its designer's 0.145 with half the spread); its still/moving, loops orbit and the other
contact misses are fewer than its designer's. Traced (Python step, seed 41 slow, 0.397, 9.0-9.6
s): its main stands, the bully pushes at a main-frame place at the touch (0.047-0.050 m), that
place 0.55-1.35 rad round the main from the live bearing (the run-up arrived from another side
than the moment's in its main's frame); the drift correction's part round the main (0.11-0.21
m/s) and the relative step's (0-0.11) stay where the main's disc holds the inward part out, so
it slides round a still main at 0.2-0.35 m/s (4.5-7.2 rad/s at 4.9 cm) where its moments (at
0.051-0.058 m) go round at 0.76 rad/s the other way: 5% of that path's steps, 25% of its orbit.
Measured (bully alone, Python step, its misses the engine's alone on seeds 0-5 / 40-45 / 300-305
/ 128-133): the correction's part round the main dropped in a charge within 1 cm of the moment's
distance, 0 / 5 / 3 / 1 -> 3 / 2 / 2 / 9 (fast and loops orbit 0.289 / 0.312 -> 0.330 / 0.341
rad/s: a main walking across then carries it round unopposed), the relative step's part too 4
/ 3 / 1 / 5; only while the live main stands (StepSenses._main_stands), five runs
(relative_motion x 1, 1 +- 0.001, 1 +- 0.002) summed 12 / 21 / 13 / 6 = 52 -> 12 / 16 / 8 / 12
= 48, all its misses 65 -> 64: orbit 23 -> 13 (slow mean 0.294 -> 0.289, spread 0.047 ->
0.031) and still/moving and contact in their place (seed 130 fast's orbit in every run); within
3 / 10 cm 8 / 9 (one run, against 9); with the relative step's part too, five runs, 13 / 18 /
3 / 9 = 43 (all its misses 57; orbit 23 -> 9, fast contact 13 -> 19), three runs on 8-13 / 26-31 5 /
7 -> 3 / 9; that with the steps since the last push counted x 1.86 in a stand, three runs, 3 /
13 / 9 / 4 -> 12 / 1 / 3 / 8 (0-5 loops orbit in each). Not kept: seeds 0-5 no lower, another
set higher in each, the totals within the re-drawing's spread (a set's count moves by 1-5
between those runs). Beside a standing main the bully's slow-path still speed is more often
under than over (seeds 26, 28, 31: 0.11-0.15 m/s, its designer 0.17-0.24, shown 0.218), and a
slide taken away there lowers it further.
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
