"""The coverage rule's bound, its share per template and studies (the rule itself is part of
:mod:`behaviors.mop.refusal`: a template drives only once its followed progress has covered
``coverage`` of its path since it engaged, or less where the template set tells its start apart).

Coverage per template (:func:`told_apart_arc`, with "scale" invariance): a template needs only as
much of its path as lies before the first state from which its path so far is the start of no other
loaded template at any size ratio shared starts try (0.31-3.3 for the size range 0.55-1.8): it
strays from each other template's start, at every size and tempo, by more than ``shape_accept``
sigma of that template's spread at its own size (not scaled by the size tried), in some column (a
per-column bound, not the path misfit, which averages over columns). ``coverage`` stays the most
asked, and a template covered sooner counts as covered, short of ``coverage``, only while its path
misfit is within :data:`EARLY_FIT` (0.25 sigma), and past it within :data:`LATE_FIT` for a while
(below). Among the six example gestures that lowers the
zigzag's alone (to 2.6% of its path, 0.15 of its progress); the other five stay another's start
past 8% of their path (the figure eight the wave's, the line the square's). Among twenty templates
the zigzag keeps 8% (a clip's start is its own), a dance's 3.5%, a run's 5.9%, a jump's 7.7%; a
template loaded alone keeps 8% (nothing to tell it from). ``bench/follow_quality.py`` (tuned;
``--sections=sequences,after,unrelated`` and ``sized,holds,shapes``): six gestures back to back,
the zigzag recognised within 20% of it 0 -> 0.67 of the time (median 0.257 -> 0.183), the open
three's share 0 -> 0.235, all six 0 -> 0.125, longest wrong run 2 unchanged, twenty templates
unchanged (0.344); unrelated motions (worst 0.068, mean 0.0143), an unrelated stroke after a
gesture (worst 0.198, 0.077 without the diagonal's figure eight, mean 0.0730), valid after 30% of
gestures at 0.7-1.4x (0.915), holds and bent shapes unchanged; ``bench/follow_widened.py`` mirrored
paths among twenty mean 0.00996 -> 0.00971 (over 0.1: 11 -> 9), worst 0.228 and sequences
unchanged. Why the fit: the true zigzag's starts keep within 0.01-0.12 sigma of its path when
covered at 2.6%; the wander of ``tests/mop/test_quality.py``'s unrelated motions (seed 11), which
goes its way for a while, 0.28-0.75. Without it (covered at 2.6% whatever the misfit): that wander
valid 0.040 -> 0.184 of its ticks with the six loaded, the bench's unrelated worst 0.068 -> 0.072
(its wander, 0.065 -> 0.072), after a gesture mean 0.0744, mirrored among twenty mean 0.01008; the
within-20% figures the same. :data:`EARLY_FIT` 0.15 and 0.25 measured alike. Measured and not kept:
the limit from ``bench/spotting_reach.py``'s observer (2 or 4 mm, no fit: the zigzag at 0.9 / 1.2%
of its path, the figure eight 1.6 / 3%, the wave 3.0 / 4.7%, the circle 7.4 / 8%): the open three
0.294 (the wave 0.14 too), but unrelated worst 0.164 (a diagonal with the six loaded: the figure
eight), after a gesture 0.298 and 0.113 without the eight; the same at 2 mm with the
:data:`EARLY_FIT` fit kept (tuned / held-out): all six within 20% 0.156 / 0.125 -> 0.188 / 0.250
(the wave 0 -> 0.14, the held-out figure eight 0 -> 0.57), twenty 0.344 / 0.344 -> 0.406 / 0.375,
but unrelated worst 0.058 / 0.094 -> 0.132 / 0.157 and after a gesture worst 0.160 / 0.176 ->
0.253 / 0.234 (the diagonal, the figure eight: its start fits a straight stroke within the fit);
at 3 and 4 mm, the kept bound below (never before the own straight start): its cost and no
held-out gain; half the misfit's refusal limit (0.6 sigma, no fit; the zigzag
1.8%): twenty templates within 20% 0.406, but unrelated worst 0.086, after a gesture 0.209 /
0.088; the refusal limit (1.2 sigma, no fit; the zigzag 3.5%): the zigzag within 20% 0.33 (median
0.203). Set by hand, not derived (the zigzag 3%, the wave 4%, the circle 5%
of their paths, no fit): the open three 0.294 (the wave 0.14), unrelated worst 0.083, after a
gesture without the eight 0.093. The wave's and the circle's starts are the figure eight's and the
line's: lowering theirs takes strokes those share.
Or sooner where the ideal observer (:data:`OBSERVER`, 2 mm) tells it apart, though never
before the template's own path leaves its chord by as much (its straight start:
:mod:`behaviors.mop.straight_start`, which holds what was measured).
A need set by the template's own straight start (above where the observer tells it apart, under the
misfit's bound and ``coverage``) is read at its best timing offset *ahead* of the followed state
(:func:`arc_ahead`: the least of commitment's shape sums within ``COMMIT_LAGS`` states,
:mod:`~behaviors.mop.commitment`, as summed up to the sample before): on a fast start the followed
state lags the performer along a stroke that has no timing of its own to tell. Read so among the
tuned twenty: the circle, jump wrist, backflip wrist and dance b wrist; held-out: the kick,
spinkick, spin and roll wrists and the crawl ankle (from rest, the 1.2x crawl ankle recognised at
0.219 -> 0.204). ``bench/follow_seeds.py``: 101-106 twenty within 20% mean 0.3125 -> 0.3177 (106
0.281 -> 0.313); 107-112 0.3177 -> 0.3281 (107 0.313 -> 0.344, 112 0.344 -> 0.375), or by reach +
0.05 0.5208 -> 0.5313 (107 and 112 0.531 -> 0.563); every other figure identical.
``bench/follow_quality.py``: every target's figure identical (the six without shared starts for
options: the line recognised at 0.277 -> 0.301, longest wrong run 6 -> 5). Price: ``bench/mop.py
--design``'s group in one process, the kernel without it and with it alternating in blocks of 25
ticks (1950 ticks each, load 3): CPU median 0.887 / 0.828 / 1.111 / 0.864 / 0.867 -> 0.897 / 0.859
/ 1.086 / 0.861 / 0.862 ms, within the noise. A need set by other templates' starts keeps the
followed state. Measured and not kept, every need under 8% read ahead (the zigzag's 2.6% among six
too): the held-out twenty's within-20%-or-reach shares up 0.005 and 0.010, but a template's own
stroke told on seed 109 0.091 -> 0.101 and unrelated told on 110 0.034 -> 0.077 (the zigzag taken
on the wander).
Read ahead also for the template least in shape leading every other not refused by ``LEAD`` 4 or 8
(``--sections=sequences``, tuned / held-out): twenty by the reach + 0.05 unchanged (0.281 / 0.531),
past the reach 0.0785 -> 0.0779 held-out, six 0.375 -> 0.406 tuned (4 only); not kept.
Less coverage for every template alike (``bench/follow_quality.py``, tuned): with every template
asked 8% of its path, what holds the open three is coverage (at 0.22-0.25 of their progress): less
coverage measured against 8% (at 8%: open share 0, the zigzag 0.257, the wave 0.225, unrelated
worst 0.068, an unrelated stroke after a gesture without the eight's ticks on the diagonal,
``after_valid_share_max_unambiguous``, 0.077): 6%: open share 0.059 (the zigzag 0.232, the wave
0.210, the figure eight 0.214), unrelated worst 0.142 (the diagonal, the figure eight; told 0.068),
after 0.102; 5%: 0.059, 0.160 (told 0.083), 0.110; no coverage and ``confirm`` 1, the ceiling:
0.647 (the zigzag 0.168, the wave 0.195; the circle 0.248, held by the other gates), 0.201 (told
0.201), 0.133; valid after 30% of gestures at 0.7-1.4x unchanged (0.915) at 6% and 5%. None is
kept: at each the unrelated worst passes 0.10 (the figure eight taken sooner on the diagonal) and
so does the after-a-gesture figure without the diagonal's eight. Coverage at 4% of the path instead
of 8% (with the tempo rule, :func:`behaviors.mop.tempo.slow_take`): the zigzag and the figure
eight at 0.21 / 0.19 (tuned / held-out), within 20% 0 -> 0.03 / 0.22 of the six gestures back to
back, but unrelated motions mean 0.085 -> 0.110 / 0.098 -> 0.122 (worst 0.305 -> 0.375); 5%: 0.106
/ 0.118; 4% with the turning rule (``turn_limit`` 1.3): 0.103 / 0.108, valid after 30% of gestures
at 0.7-1.4x 0.8959 / 0.9115: no rule tried refuses what coverage refuses without holding the zigzag
back.

Coverage counts only arc the performance went along: a template counts as covered only while its
followed progress's arc from its start is at most :data:`RUN_AHEAD` times the input's farthest
reach from its anchor since the performance began (both RMS per column in the template's
spread, at its size; the last samples averaged as engagement reads them). The bound bites only
where the followed state runs far ahead of anything the input did.

Why: the forward floor (:func:`behaviors.mop.window_kernel.step_windows`) keeps probability on
every state of the window, and a window of half-width 23 or more holds the whole line (46
states), whose end lies 0.11 sigma from its start. On a still puck the end state, matching it,
gains and wins after 3-8 s: the followed arc climbs 0.14 -> 4.65 (the line's whole path) over
15-20 samples while the input moves nowhere, and coverage counted it (``tabletop follow``'s
defaults, features as recorded, the six example gestures, 10 s still with 0.7 mm jitter, 40
draws: with ``--window`` 25 or 40 18 draws valid, up to 240 of 300 samples, 0.312 of the time;
none with 15 or with a puck's settings). There the followed arc is 20.6 or more times the
input's reach (10th percentile of the covered samples, the least draw); on true performances
(every template of ``bench/follow_quality.py`` at 0.7, 1 and 1.4x) at most 11.1 (follow's
defaults: a 0.7x figure eight at its end; 8.9 with a puck's settings). Measured with 15: the
still draws at windows 15, 25 and 40 valid on none of 40, either settings;
``bench/follow_quality.py --sections=sized,sequences,unrelated,after`` every tuned and held-out
figure identical (20: the same).

Measured and not kept: the arc asked for coverage (8% of the path) bounded when it is reached by
a multiple of the input's *current* reach: on true performances that need is up to 2.14 times
the reach when covered (the line at 0.7x with follow's defaults, its size not estimated), while
a still line's need is 1.69 times the jitter's reach at the least; 1.5 took every still draw
to 0, but valid after 30% of gestures at 0.7-1.4x 0.9157 -> 0.9124 (held-out 0.9049 -> 0.8899)
and gestures back to back among twenty recognised within 20% 0.344 -> 0.313 (mocap paths that
curve: their arc runs ahead of their chord); 1.8: 0.9138, 0.313; 2.0: 0.9147, held-out 0.8949.
A bound on each sample's advance by that sample's own displacement does not tell the still line:
a jitter step in its narrow column (spread 0.01 m) is 0.07 units, as large as a 0.7x stroke's
step. The input's own travel *in place of* the followed arc delayed recognition (see
below).

Coverage and gestures back to back, with every rule since in place (``bench/follow_quality.py
--sections=sequences``, tuned / held-out; within 20% = each of the six gestures back to back
recognised within 20% of it, 0 / 0 at 8%; twenty templates 0.344 / 0.344; unrelated motions' mean
valid share 0.0576 / 0.0607). Coverage 8% of the path is reached at 0.20-0.24 of every gesture
(eased starts), the followed progress's arc *ahead* of the input's own. Measured, not kept: no
coverage at all, the ceiling of any coverage rule: within 20% 0.16 / 0.25 (twenty 0.41 / 0.38; the
other gates then hold the rest). 4%: unrelated mean 0.0766 / 0.0758 (wander with the circle alone 0
-> 0.2 of the time). The input's own travel instead of the followed arc (in the template's spread
at its size, counted in steps of 2 or 4 still radii so the jitter adds none): within 20% 0 / 0, the
zigzag later (median 0.257 -> 0.285), twenty 0.25 / 0.34; its net displacement against the
template's where 8% is covered: zigzag 0.436. 4% while the template is at least 0.95 probable
(threshold model counted): 0.03 / 0.22, unrelated mean 0.0711 / 0.0739; 4% at an estimated size of
0.9x and up (no probability asked; the size is still about 1 that early): 0.06 / 0.22, 0.0766 /
0.0753. 4% (or none) only in an attempt begun where the last gesture ended, not from rest (a
performer going on from one gesture to the next): 0.03 / 0.16, twenty 0.375 / 0.375, from-rest
unrelated mean 0.0577 / 0.0609, held-out twenty longest wrong run 11 -> 13, but an unrelated stroke
right after a gesture (each of the six, then a diagonal, triangle, spiral or wander at 0.7-1.4x, no
rest) valid 0.113 -> 0.139 of its ticks (not a start of the action driving, as the bench's
``told``: 0.075 -> 0.077); with the 0.95 probability too: 0.03 / 0.16, twenty unchanged, 0.134.
Every coverage that lets a start drive sooner lets a stroke that follows the start's direction
drive as soon: the zigzag, figure eight and wave are told from the *other templates* at 9-13% only
by the direction of their first stroke, which an unrelated stroke shares.

Coverage and gestures back to back again, with the drift, take-fit and own-confirmation rules in
place (``bench/follow_quality.py --sections=sequences`` and ``--sections=unrelated,after``, tuned;
before: among the six gestures within 20% 0, median recognition 0.259; unrelated worst / mean
0.228 / 0.0394; an unrelated stroke straight after a gesture worst / mean 0.198 / 0.079, the
diagonal 0.154). Traced tick by tick on the bench's draws (with ``bench/spotting_reach.py``'s gates,
medians): the zigzag passes every other rule from 0.18 of it and waits for coverage (0.24,
recognised at 0.257); the figure eight leads from 0.20 and is covered at 0.22 (0.244); the wave
and the circle become best only by commitment (:mod:`~behaviors.mop.shape_lead`), which waits
for coverage (0.21 / 0.23; recognised at 0.225 / 0.262, the circle also held by the line's
shared stroke to 0.25); the confirmation then adds a sample (0.013-0.02 of the gesture). Measured,
not kept: 6%: within 20% 0.031 (zigzag 0.231, figure eight 0.214, wave 0.210), unrelated worst
unchanged, mean 0.0466, after a gesture 0.276 / 0.0985 (the diagonal 0.205; ticks where it is
no start of the action driving, worst 0.096 -> 0.127); 4%: 0.063, unrelated mean 0.0556, after
0.298 / 0.110. The confirmation counted over the samples a choice passed every rule but
coverage (it drives as soon as it is covered): zigzag 0.241, figure eight 0.222, within 20% 0,
after 0.216 / 0.083 (each diagonal a sample sooner); with 4% 0.094. ``confirm`` 1: within 20%
0, after 0.240 / 0.102. The ceiling of both (no coverage, ``confirm`` 1): within 20% 0.41
(zigzag 0.168, figure eight 0.200, wave 0.195; the circle 0.248, the line 0.43 and the square
0.397 wait for their rivals), longest wrong run still 2. The figure eight's first stroke lies
within 4 mm of the diagonal up to 0.22 of it (``bench/spotting_reach.closest_start``): whatever
takes the eight before it turns takes the diagonal as soon. The zigzag's (19 mm off at 0.15 of
it) goes where none of the bench's unrelated strokes go: a coverage lowered for it alone would
be chosen by the bench's strokes, not by anything the input shows.

Why recognition lags the observer's reach: by 20% of their progress the six example gestures
(``examples/mop/gestures``, eased starts) have covered 4.5-8% of their path (18-39 mm from their
start), and their path so far strays from the straight chord start -> there by at most 0.9-1.8
mm, within the 2 mm the observer calls alike: each is still a straight stroke. The observer
(``bench/spotting_reach.py``) tells the zigzag, figure eight and wave from the *other templates*
at 0.09-0.13 of them by that stroke's direction alone; any straight stroke in that direction is
as much their start, and the unrelated and after-a-gesture figures count those strokes. A
sequential decision in place of coverage, measured and not kept (Wald's test: a template counts
as covered once its probability against every other template and the threshold model, the
``min_probability`` read, reaches 1 - alpha; ``--sections=sequences,after,unrelated``, tuned):
the true template's probability first reaches 0.99 at (medians of ``spotting_reach``'s draws)
circle 0.30, zigzag 0.20, figure eight 0.22, line 0.28, square 0.40, wave 0.34, later than
coverage (0.21-0.25) for all but the zigzag: the evidence tells no sooner than coverage does.
Alpha 1e-4: the zigzag 0.257 -> 0.237, every other gesture the same, within 20% (or reach) 0
unchanged, but unrelated mean 0.0154 -> 0.0158 (one template loaded 0.0077 -> 0.0101, a
triangle and a wander: with one template only the threshold model competes); on the tuned
joints, seeds 201-210 (``evaluate(puck_follower, seed)``, means): zigzag 0.260 -> 0.247, within
20% (or reach) 0.016 unchanged, unrelated mean 0.0209 -> 0.0215 (worse on all ten seeds), after
a gesture mean 0.0749 -> 0.0777, told worst 0.097 -> 0.110. Alpha 1e-3 with at least 4% of the
path covered: zigzag 0.230, within 20% 0, unrelated worst 0.068 -> 0.118, mean 0.0196, after
worst 0.198 -> 0.217. Alpha 1e-6 and 1e-9: identical to coverage alone. Coverage 4% where the path
bends (measured, not kept): while the input's mean bulge off its chord (signed area between its
path from the anchor and the chord, over the chord) is at least ``h`` and the template's path to
the followed state bulges the same way by ``r`` of that at its size. Noise-free, the six gestures'
mean bulge is 0.0-0.3 mm up to 0.18 of them, the jitter's over 10-20 samples about 0.2 mm: from
rest (h 0.3 mm, r 0.5), the true template qualified on 5-16% of its ticks at 0.10-0.20, the six on
5-20% of a diagonal's first half, up to 45% of a triangle's. Tuned: within 20% 0 -> 0.031 (the
figure eight, its start straight, 0.244 -> 0.222), twenty 0.344 -> 0.406, but unrelated worst /
mean 0.068 / 0.0154 -> 0.105 / 0.0202, after a gesture worst 0.198 -> 0.241; h 0.2 mm, r 1: within
20% 0, 0.105 / 0.0199, 0.230; h 0.5-1 mm: at most 0.007 sooner (``bench/spotting_reach.py``). The
bend shows no sooner than the arc.

The circle and the wave back to back, what holds each past the observer's reach
(``bench/spotting_reach.earliest`` pairwise, 2 / 4 mm; ``bench/follow_quality.py``'s draws for
options, 16 sequences, with ``bench.spotting_reach.gates``). The circle is told from the line at
0.20 / 0.22 of it and from the square at 0.19 / 0.22 (from the zigzag, figure eight and wave at
0.09-0.14): out of reach by 20%, whatever the follower. Its shape sums
(:mod:`~behaviors.mop.shape_lead`) lead the nearest rival by 1 nat at 0.217 of it (median; 1 of 11
by 0.20), by 4 at 0.241; with no coverage and no shared start for it and ``LEAD`` 2 and
``COMMIT_FIT`` 3 its recognition stays at 0.272 (within 20% 0). The wave is told from the figure
eight at 0.13 / 0.16 (from the other four at 0.07-0.12): open, but coverage is not what holds it
there. With no coverage for it alone its recognition median 0.248 -> 0.238, within 20% 0 -> 0: then
it waits for its start shared with the figure eight's (:mod:`~behaviors.mop.sharing`, 3 still radii,
5.7 mm in x and 2.9 mm in y, the still radius set per column by the narrowest template: to state 9,
0.16 of it; the gate clears at 0.20) and for commitment
(:meth:`~behaviors.mop.shape_lead.ShapeLead._committed`: its shape sums lead the figure eight's by 1
/ 2 / 3 / 4 nats at 0.153 / 0.164 / 0.176 / 0.188, medians, 4 by 0.20 in 8 of 13, but its own sum is
within ``COMMIT_FIT``, 1.75 still radii, in only 2 of them then: one draw 2.0 at 0.22; read at its
best size, 4, while coverage holds it to 0.224: :mod:`~behaviors.mop.shape_lead`); the
evidence meanwhile prefers the figure eight (narrower in x, 56 mm against 77: 0.27 nats a sample)
until 0.22-0.28. The wave's share within 20% with no coverage for it and each further rule lifted:
``LEAD`` 2: 0.077; ``COMMIT_FIT`` 3: 0.077; no shared start for the wave: 0; the last two: 0.31; all
three: 0.54 (median 0.200). On the bench (``--sections=unrelated,sized,sequences``, tuned /
held-out; before: the wave within 20% 0 / 0, all six 0.125 / 0.125, unrelated worst 0.065 (the
wander among six) / 0.247 (a mirrored joint among twenty), told worst 0.057 / 0.090, valid after 30%
at 0.7-1.4x 0.912 / 0.903), measured and not kept: no coverage and no shared start for the wave
alone: the wave 0.29 / 0.50 (median 0.225 -> 0.205 / 0.229 -> 0.204), all six 0.188 / 0.188,
unrelated worst 0.072 / 0.247, told and sized unchanged, but it is set for one template by hand: its
start is a straight stroke to 0.25 of it, and any stroke in its direction would drive it as soon
(the zigzag's above: chosen by the bench's strokes, not by the input). ``LEAD`` 2 and ``COMMIT_FIT``
3 for every template: all six 0.156 / 0.125, unrelated worst 0.081 / 0.293, told worst 0.066 / 0.135
(the held-out mirrored joints among twenty), sized 0.918 / 0.904; with the wave's exemptions too:
the wave 0.86 / 0.75, all six 0.344 / 0.219, unrelated worst 0.111 (the wander among six) / 0.293,
told worst 0.066 / 0.135. What delays the wave past 0.16 is the shared start's radius and the
commitment's own-fit and lead limits, rules of every template, not its coverage; a coverage derived
from its distinctiveness at the sharing radius (5.7% of its path, covered at about 0.19) asks no
less than the shared start already holds. The shared start and this coverage both judged at an
isotropic 3 still radii (2.86 mm in each column; the wave's start shared to its state 8, 4.6% of its
path): the wave 0.29 / 0.50, all six 0.188 / 0.313 (the figure eight 0 / 0.57), twenty templates
0.344 -> 0.406, but the diagonal among six 0.064 -> 0.160 (the figure eight taken on its start), the
held-out twenty's longest wrong run 11 -> 14; on the draws for options the wave's recognition stays
at 0.238 (within 20% 0).
Tick by tick on the bench's own draws (``bench/follow_quality.py --sections=sequences``, the six
gestures' eight sequences, tuned / held-out; for the gesture performed, the progress from which
each rule held without a break until it drove, medians; ticks counted from the first at its
observer reach: circle 0.20, zigzag 0.09, wave 0.13). The wave (7 / 4 performed), recognised at
0.225 / 0.229, 7 / 7.5 ticks after its reach: engaged at its reach, leads in shape (``LEAD``) from
+3 / +4 ticks (0.179 / 0.192), its start shared with the figure eight's until +4 / +5 (0.195 /
0.196), covered at +6 / +6.5 (0.211 / 0.217), and on that tick committed to
(:mod:`~behaviors.mop.shape_lead`: best and probable, the eight keeping 0.44-0.85 of the
probability), then the confirmation's sample. The zigzag (6 / 5), 0.183 / 0.173 (+5.5 / +7):
engaged and no longer shared at +2.5 / +2 (0.141 / 0.127), covered (its 2.6%) at +4.5 / +6 (0.161 /
0.159); committed on that tick unless its shape sum fails ``COMMIT_FIT`` (2.0-2.7 still radii, its
path misfit 0.02-0.08 sigma: the follower lags the fast zigzag; 4 of 6 tuned), then best only by
the evidence 1-2 samples later (0.59 probable at 0.191: driving at 0.248; 0.37 at 0.156: 0.204;
read at its best timing offset, :mod:`~behaviors.mop.commitment`, that one is committed to at 0.156
and drives at 0.180). The circle (4 / 4), 0.262 / 0.266 (+3.5): covered, leading and unshared
together at +2 / +2.5 (0.234 / 0.248). On the draws for options (16 sequences) the same: the wave
(13) covered after the shared start in all and after the lead in 12, +5 ticks (0.224; shared to
0.202, leading from 0.188), best 0-2 samples after it where ``COMMIT_FIT`` fails (7 of 13); the
zigzag (9) covered at +5 (0.159), best 0.172; the circle (11) every rule at +2 (0.246-0.248).
Measured and not kept (the whole bench, against the same figures before): the confirmation's sample
waived for an action committed to: the wave 0.211 / 0.217, the circle 0.248 / 0.250, within 20%
unchanged (0.125 / 0.125), unrelated worst 0.058 -> 0.067 / 0.099 -> 0.102, after a gesture (told)
0.072 / 0.083 -> 0.089; waived also at 0.9 probable: within 20% 0.156 / 0.125 (the zigzag),
unrelated worst 0.075 / 0.110, after a gesture 0.078 / 0.094, held-out twenty's longest wrong run
11 -> 12.
Three further forms, measured and not kept (``bench/follow_quality.py``, tuned / held-out; before:
six gestures back to back within 20% 0.156 / 0.125, twenty templates 0.344 / 0.344, unrelated worst
0.058 / 0.099 (a wander among six; the diagonal among six), after a gesture worst 0.165 / 0.189
(told 0.072 / 0.083), valid after 30% at 0.7-1.4x 0.912 / 0.902). A sequential test in place of
the fixed share: a template counts as covered also once its evidence leads the threshold model's
(:mod:`behaviors.mop.threshold`, both forgotten alike since the gesture began) by ``B`` nats, while
within :data:`EARLY_FIT` of its path and not run ahead (:data:`RUN_AHEAD`). On the bench's draws
that ratio grows about a nat a sample along every start, a clock as the arc is: where the shared
start lets go it reads 5-8 nats for the wave and 7-11 for the figure eight (narrower, so sooner).
``B`` 6: within 20% 0.188 / 0.250 (the wave 0 -> 0.14 / 0, the figure eight 0 / 0 -> 0.57), but
unrelated worst 0.141 / 0.157 (the diagonal among six, the figure eight; a wander with one template
loaded 0.007 -> 0.067), after a gesture worst 0.258 / 0.248; with the confirmation waived where the
action led in shape for ``confirm`` samples before its last rule cleared: within 20% 0.219 / 0.281,
twenty 0.406 / 0.406, sized 0.919 / 0.910, unrelated worst 0.144 / 0.161, after 0.258 / 0.256. The
same test against the best other template instead (``B`` 2 or 4, the Wald test above at a low
bound): no gesture sooner (the wave leads the figure eight in evidence only from 0.22).
Coverage as a fixed arc in the template's own spread (its columns standardised: 0.55 or 0.6 for
every template, the told-apart arc where less; 8% of the path is 0.58 for the circle, 0.67 the
wave, 0.92 the figure eight, 0.34 the line): tuned within 20% unchanged (the wave 0.211-0.215),
held-out the figure eight 0 -> 0.57 (at 0.55), taken on the diagonal's start. The confirmation's
sample waived where the action led every template in shape by ``LEAD`` for ``confirm`` samples
before coverage cleared (on the tick it clears): within 20% unchanged (the wave 0.225 -> 0.215,
the fast zigzag's draw unchanged, 0.248: best only a sample after it is covered), twenty 0.344 /
0.375, but unrelated worst 0.067 / 0.110, after a gesture 0.183 / 0.208 (the diagonal's figure
eight a sample sooner). :data:`~behaviors.mop.commitment.COMMIT_LAGS` 5 or 8: no gesture
sooner (that zigzag's timing changes sample by sample). At the sharing radius (3 still radii,
:func:`~behaviors.mop.sharing.shared_until`) the figure eight is told from every other template at
4.5% of its path (0.17 of it), the wave at 5.7% (0.18): every rule derived from the template set,
the evidence or the template's spread frees the figure eight no later than the wave, and the figure
eight's start is the diagonal.
Twenty templates back to back (``bench/follow_quality.py``'s within 20%: the share of gestures
whose first tick driven by their own action comes at most 0.2 into them, in the template's time):
coverage sets it. 8% of the path lies at 0.22-0.29 of the progress for ten of the tuned twenty (the
held-out backflip ankle 0.37, jump ankle 0.33), 0.20 for the line and the roll ankle, 0.04-0.13
for the other eight. Tuned, the 11 gestures of 32 recognised within 20% are exactly the 11 whose
template is covered by 0.18; held-out, 10 of those 14, the other four punch ankles (which no
observer tells from the getup wrist by 0.25, ``bench/spotting_reach.py``), and one fast figure
eight. Measured and not kept (``bench/follow_seeds.py --sections=sequences,unrelated``, held-out
seeds 101-106): ``confirm`` 1, twenty within 20% mean 0.260 -> 0.323, but the longest wrong run
longer on five seeds (4/5/7/2/2/4 -> 4/6/8/3/4/5) and unrelated worst 0.117 -> 0.194.
What else holds the tuned twenty's late gestures (``bench.spotting_reach.gate_state`` per tick on
the bench's draws: the progress from which each rule held until the gesture drove): the kick
ankle (3 draws, recognised 0.35-0.39) covered at 0.28-0.33, unshared from 0.25-0.26, probable and
best from 0.32-0.33; the spinkick ankle (3, 0.33-0.36) covered 0.28-0.30, unshared 0.26-0.28,
probable 0.31-0.33; the spin ankle (2, 0.38-0.40) covered 0.30-0.33, unshared 0.34-0.36; the punch
wrist (0.39) engaged only at 0.29; the roll ankle (0.23-0.33) covered at 0.20-0.21, probable at
0.17-0.31; the line and the square shared to 0.37-0.41. Coverage met sooner leaves each of them
past 0.2 (the ceiling with no coverage at all, 0.41, above).
Held out, the zigzag covered at 2.6% drives the seeds' wanders after a gesture (taken at
0.155-0.183 of it where the observer tells it from them by 0.08-0.14; traced in
:mod:`~behaviors.mop.shape_lead`). Measured and not kept, :data:`EARLY_FIT` 0.25 -> 0.12
(``bench/follow_seeds.py``, 101-112): after a gesture worst 105 0.214 -> 0.192, 106 0.178 ->
0.110, 107 0.302 -> 0.243, 111 0.149 -> 0.143, but twenty templates within 20% 102 0.406 ->
0.344, 105 0.219 -> 0.188, 106 0.313 -> 0.281, 107 0.344 -> 0.313, 112 0.375 -> 0.344 (the
clips covered sooner); 0.18: 107 0.282, 102 still 0.344; 0.06: 107 0.161, tuned six within 20%
0.156 -> 0.125, twenty 0.406 -> 0.344. Past 8% of its path (0.24 of it) the zigzag is covered
whatever its fit, where most of those ticks lie.
The early coverage held to the misfit since the template engaged, measured and not kept
(``bench/follow_seeds.py --seeds=105,106,107,111 --sections=after,sequences,sized``; before: after a
gesture worst 0.214 / 0.178 / 0.302 / 0.149, sized 0.920 / 0.910 / 0.925 / 0.907). Its mean or its
largest within :data:`EARLY_FIT` besides the current: nothing moves (sized 107 0.924). On 107's
circle then wander at 0.7 the zigzag engages 20 samples in at 0.02, is best at 24 at 0.025 and
drives 25-30 as its misfit rises to 0.23 (so its largest since), is uncovered from 31 (0.30, 0.61 by
37) and covered again at 40 by 8% of its path at 0.43-0.57, driving 43-58. Its largest while short
of 8% held past it (uncovered for the rest of the performance once over): 0.25: after 0.158 / 0.071
/ 0.168 / 0.149, but sized 0.800-0.815, twenty within 20% 106 0.313 -> 0.281; 0.4: after 0.158 /
0.178 / 0.168 / 0.149, sized 0.891-0.897. Counted only from its first sample covered short of 8%:
0.25 sized 0.823-0.852 (within 20% as at 0.25 above); 0.4 sized 0.910 / 0.901 / 0.905 / 0.897; 0.5
and 0.58 after 0.158 / 0.178 / 0.168 / 0.149, sized 0.910 / 0.910 / 0.915 / 0.907, within 20%
unchanged. 0.5 on 101-112: after 103 0.082 -> 0.080, 105 0.158, 107 0.168 (106 0.178, 111 0.149, 110
0.101 unchanged), sized 103 0.921 -> 0.911, 104 0.914 -> 0.904, 105 0.910, 107 0.915, unrelated told
103 0.043 -> 0.030, 106 0.044 -> 0.031, 109 0.064 -> 0.049, but twenty within 20% 108 0.313 -> 0.281
(with reach 107 0.563 -> 0.500, 108 0.656 -> 0.625); ``bench/follow_quality.py``: sized 0.6-1.5
edges valid after 30% 0.760 -> 0.620 (held-out 0.767 -> 0.743), recognised by the end 0.975 ->
0.800, six gestures never recognised 0 -> 0.016 (a true gesture off its path early stays
uncovered).
Past ``coverage`` of its path a template covered sooner is held to its path a while longer: within
:data:`LATE_FIT` (0.3 sigma) until it has gone on past ``coverage`` by :data:`LATE_UNTIL` (1.5)
times the arc it was let off (the zigzag among six, let off 68% of it, to 16% of its path, about 0.3
of it; the circle, let off 9% by its straight start, to 9.1%). Traced per tick
(``bench/follow_seeds.py --sections=after``, the seeds' wanders after a gesture): on 105 and 106 as
on 107 above, the zigzag taken at 0.16-0.17 of it and driving at 0.24-0.29 off its path by 0.33-0.68
sigma (107's square then wander at 0.7: 0.33 where the wander comes to rest at 0.248 of it; 105's:
0.56-0.68 at 0.28-0.29); on 111 the worst is the wave, covered at the ordinary 8% (0.26 of it) and
driving to 0.44 off its path by 0.47-0.85: no rule on early coverage answers it. On 105's wanders at
1.4x the zigzag keeps within 0.14-0.25 of its path to 0.28 of it: no fit tells those.
``bench/follow_seeds.py``, 101-112: after a gesture worst 105 0.214 -> 0.137, 106 0.178 -> 0.071,
107 0.302 -> 0.095 (110 0.101, 111 0.149 unchanged), unrelated told worst 104 0.079 -> 0.073, a
template's own stroke told 108 0.095 -> 0.076, 109 0.091 -> 0.065; sized and every back-to-back
figure identical. ``bench/follow_quality.py``: tuned sized valid after 30% at 0.7-1.4x 0.9207 ->
0.9189, pauses held through 0.957 -> 0.942, own stroke told worst 0.050 -> 0.037; every back-to-back
figure and after worst identical. Measured and not kept: 0.4 over the whole path past ``coverage``:
after 105 0.141, 106 0.080, 107 0.135, but held-out sized 0.873-0.888 on 101-106 (the kick,
spinkick, roll and spin wrists, covered early by their straight starts, run 0.4-0.7 off their paths:
on 103 the 0.7x roll wrist 0.902 -> 0); 0.3 to twice ``coverage`` for every template: after as kept,
108's longest avoidable wrong run among twenty 3 -> 2, but twenty within 20% or by reach + 0.05 107
0.563 -> 0.531, 108 0.656 -> 0.625 (the crawl ankle, let off 32%, recognised 0.231 -> 0.269; the
circle among six 0.296 -> 0.344); 0.3 or 0.4 to 1.5 times ``coverage``: 105 0.211 (the zigzag
driving past it). For templates covered at ``coverage`` (111's wave), not kept: 0.5 to three times
it: after 110 0.101 -> 0.076, 111 0.149 -> 0.108, but six within 20% or by reach + 0.05 101 0.500 ->
0.469, twenty within 20% 108 0.313 -> 0.281, sized 108 0.906 -> 0.901; 0.45-0.5 to twice: 111
0.131, held-out six by reach + 0.05 0.500 -> 0.469 (``bench/follow_quality.py``). 110's worst is one
motion, the wave then the diagonal (0.7x 0.138), the figure eight driving much of it on its path.
Traced again (``bench/follow_seeds.py``): 111's wave on the wanders reaches ``coverage`` 0.56-1.05
sigma off its path and its misfit then *falls* (0.42-0.77) as it drives; true gestures back to back
reach it as far off (the held-out figure eight 0.57 / 0.71 on 101 / 102), a 0.7x one before its size
is known too (the zigzag 0.64-0.92). Not kept, for templates asked all of ``coverage``, to three
times it, uncovered until within ``f`` of its path on some sample past it: 0.5: after 110 0.101 ->
0.076, 111 0.149 -> 0.120, but sized lower on 8 of 12, six by reach + 0.05 101 0.500 -> 0.469; 0.4:
111 0.096, but twenty within 20% 110 0.406 -> 0.375; 0.4 only where it reached ``coverage`` over 6
samples after engaging (built in the follower and the group's kernel alike): 111 0.096, 107 / 109
0.095 / 0.090 -> 0.091 / 0.086, every back-to-back figure the same on 101-112, the tuned 0.6 / 1.5x
recognised by their end 0.975 -> 0.95, and on 113-118 (never tuned on) no after worst moved (116
0.107) while sized fell 0.0032 on 113 (0.9197 -> 0.9164; 111 0.9071 -> 0.9040): the gain is 111's
alone. The misfit's trend (uncovered while over 0.3 sigma and over its least since by 0.1): 111
0.140, sized 111 0.907 -> 0.894. 105's zigzag where it first drives on the wanders (21 draws)
against 67 true ones back to back: progress 0.151-0.178 / 0.158-0.22, speed 0.8-3.9 / 2.4-18 mm a
sample, 12-22 / 16-38 mm from the anchor, misfit 0.09-0.21 / 0.02-0.07: none parts them with a
margin.
"""

from __future__ import annotations

import numba
import numpy as np

from behaviors.kernel_cache import compiled
from behaviors.mop.sharing import shared_until
from behaviors.mop.spotting import SHARE_SKIP

#: The ideal observer's likeness (``bench/spotting_reach.py``; raw units, metres on the table):
#: two paths closer than this everywhere cannot be told apart, nor a path from its own chord.
OBSERVER = 0.002
#: A template counts as covered only while its followed arc is at most this many times the
#: input's farthest reach since the performance began (both in the template's spread).
RUN_AHEAD = 15.0
#: Below ``coverage`` of its path (covered sooner, :func:`told_apart_arc`), a template counts as
#: covered only while its path misfit is at most this (sigma).
EARLY_FIT = 0.25
#: Past ``coverage`` of its path, a template covered sooner counts as covered only while its path
#: misfit is at most this (sigma), until it has gone on past ``coverage`` by :data:`LATE_UNTIL`
#: times the arc it was let off (``coverage`` less its need).
LATE_FIT = 0.3
#: ... (a multiple of the arc let off; past it every template counts as covered whatever its fit).
LATE_UNTIL = 1.5



def told_apart_arc(rel: np.ndarray, starts: np.ndarray, lengths: np.ndarray, arc: np.ndarray,
                   scale: np.ndarray, sizes: np.ndarray, radius: float) -> np.ndarray:
    """Per template, the arc of its path (``arc``: per state, from its first) at the first state
    from which its path so far is the start of no other template at any of ``sizes``: it strays
    from every other template's (both from their first points, ``rel`` in raw units; the other's
    scaled by each size tried) by more than ``radius`` times that template's spread (``scale``
    (K, d), not scaled by the size) in some column, a per-column bound, not the path misfit
    (:func:`~behaviors.mop.sharing.shared_until`); its last state's arc when never. Infinite for
    a set of one (nothing to tell it from)."""
    if len(starts) < 2:
        return np.full(len(starts), np.inf)
    until = shared_until(rel, starts, lengths, sizes, radius * scale, SHARE_SKIP)
    told = np.minimum(until.max(axis=1) + 1, lengths - 1)
    return arc[starts + told]


@compiled(numba.float64(numba.float64[:, :], numba.intp, numba.float64, numba.intp, numba.intp,
                        numba.float64[:, ::1], numba.intp, numba.intp))
def arc_ahead(lags: np.ndarray, k: int, g: float, first: int, last: int, states: np.ndarray,
              off: int, col: int) -> float:
    """Template ``k``'s arc (``states``' column ``col``, its rows from ``off``) read at its
    followed state ``g`` (bank index; its states ``first`` .. ``last``) plus its best timing
    offset, the least of its shape sums ``lags`` (one row per offset:
    :func:`~behaviors.mop.commitment.add_lagged`; ties to the one most behind), where that
    lies ahead; at ``g`` otherwise (the follower and the group's kernel call it alike)."""
    n = lags.shape[0]
    best = 0
    for j in range(1, n):
        if lags[j, k] < lags[best, k]:
            best = j
    at = min(g + max(best - (n - 1) // 2, 0), float(last))
    jl = max(min(int(at), last - 1), first)
    a = states[jl + off, col]
    return a + (at - jl) * (states[min(jl + 1, last) + off, col] - a)

