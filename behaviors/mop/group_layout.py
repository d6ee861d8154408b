"""The data layout of a follower group's compiled arrays: which column or row of ``states``,
``tc``, ``mc``, ``floats`` and ``flags`` holds which template state, template scalar or member
scalar. :class:`behaviors.mop.group_arrays.GroupArrays` fills them in this order and
:mod:`behaviors.mop.group_kernel` (and its helpers in :mod:`behaviors.mop.members` and
:mod:`behaviors.mop.member_validity`) read them by these positions.
"""

from behaviors.mop.commitment import COMMIT_LAGS

#: Columns of the per-state array ``states`` (S, 2D + 5), one row per template state of the
#: group (D: the widest member's features): its mean (D, raw template units), its place relative
#: to the template's first in units (D), its progress (``source``) and its path length from the
#: first state. Read around each followed state: one contiguous stretch per template (the
#: per-template pass is bound by reading memory; six separate arrays cost 1.5x).
STATE_COLUMNS = ("means", "rel", "source", "arc", "hold_end", "hold_ahead", "hold_begin")
#: Per-template scalars (columns of ``tc`` (K, 6 + 4D), then the rows ``scale``, ``center``,
#: ``ufirst``, ``c_off`` of D columns each, then :data:`TEMPLATE_LAST`).
TEMPLATE_SCALARS = ("_jacobian", "_onset_state", "_prior", "_arc_need", "_reach_inv")
TEMPLATE_ROWS = ("_scale", "_k_center", "_k_ufirst", "_k_c")
#: ... and ``tc``'s last column: 1 where coverage reads ahead
#: (:func:`behaviors.mop.coverage.arc_ahead`), else 0.
TEMPLATE_LAST = "_read_ahead"
#: Per-member scalars (columns of ``mc`` (M, 39 + 2D + L), then the rows ``radius`` and
#: ``units`` (D each) and :data:`~behaviors.mop.take_rule.TAKE_SIZES` from the estimate outwards
#: (L); ``threshold`` infinite where a member has no threshold model). The rules' constants
#: among them are read where the group is built, as the followers' own constants are, so a
#: group built with one changed follows that value, as its followers alone do: ``take_fit2``
#: (:data:`~behaviors.mop.shape_lead.TAKE_FIT` squared), ``carry_first``
#: (:data:`~behaviors.mop.validity.CARRY_FIRST` as :func:`~behaviors.mop.validity.stalls` and
#: :func:`~behaviors.mop.validity.carried` read it; halts' gate takes it compiled in, as
#: :class:`~behaviors.mop.recognition.Recognition` imports it), ``crawl_samples`` and
#: ``crawl_hovers`` (:data:`~behaviors.mop.tempo.CRAWL_SAMPLES`, ``CRAWL_HOVERS``: 1 or 0),
#: ``unjudged_at_rest``, ``unweighed_at_rest`` (:data:`~behaviors.mop.validity.UNJUDGED_AT_REST`,
#: ``UNWEIGHED_AT_REST``: 1 or 0), ``rest_behind`` and ``taken_performed``
#: (:data:`~behaviors.mop.validity.REST_BEHIND`, ``TAKEN_PERFORMED``), ``early_fit2``
#: (:data:`~behaviors.mop.coverage.EARLY_FIT` squared), ``tempo_end_from``
#: (:data:`~behaviors.mop.handover.TEMPO_END_FROM` as :mod:`~behaviors.mop.spotting` imports
#: it), ``arrive_radius`` (:data:`~behaviors.mop.gesture_end.ARRIVE_RADIUS`), ``rested_lifts``
#: (:data:`~behaviors.mop.validity.RESTED_LIFTS`: 1 or 0), ``late_fit2`` and ``late_until``
#: (:data:`~behaviors.mop.coverage.LATE_FIT` squared, ``LATE_UNTIL``).
MEMBER_SCALARS = ("dims", "decay", "null_decay", "log_constant", "two_over", "null2", "accept2",
                  "onset_sigma", "scaled", "lo", "hi", "misfit_decay", "shape2", "shape_accept2",
                  "path_scale", "spots", "none", "margin", "threshold", "thr_factor", "thr_const",
                  "rejudge_at", "keep", "reversal_move2", "coverage", "take_fit2", "carry_first",
                  "crawl_samples", "crawl_hovers", "unjudged_at_rest", "unweighed_at_rest",
                  "rest_behind", "taken_performed", "early_fit2", "tempo_end_from",
                  "arrive_radius", "rested_lifts", "late_fit2", "late_until")
#: Templates ahead whose states are fetched while one is worked on (:mod:`behaviors.mop.compiled`).
#: 4 ahead (DESIGN's tick, alternating processes, load 18-22): update_templates p10 731, 770 ->
#: 691, 749 us, but the tick's median 1990 -> 2025 us in the second pair: not taken.
AHEAD = 2
MC_ROWS = len(MEMBER_SCALARS)
#: Per-template float state updated in place: the columns of ``floats`` (K, len(FLOATS)), in
#: this order, so that one template's state is one record (as ``states``' rows and ``tc``'s).
#: As rows (len(FLOATS), K) the per-template pass read and wrote one column of 25 rows and 8
#: flag rows, ~40 streams, more than the processor follows (prefetching the 25 rows ahead won
#: ~44 us of it; the flag rows as well was slower). update_templates alone on 100
#: captured ticks of DESIGN's group after 48 MB touched (the installation's case), the same
#: outputs to the bit, paired per round: -162.2, -141.0, -108.9 us (load 11, of ~1430);
#: -76.6, -103.3, -56.2 and, the sides swapped, -55.7, -67.3, -16.6 (load 6-9, of ~1230);
#: hot -64.8, -9.6, -8.5 (medians of three rounds).
FLOATS = ("_evidence", "_recent", "_recent_weight", "_num", "_den", "_size", "_misfit_w", "_shape",
          "_gone", "_least", "_judged", "_drift", "_drift_run", "_reached", "_attempt_from",
          "_rev_undo", "_rev_at", "_seat")
#: Per-template shape sums at each timing offset (:func:`behaviors.mop.commitment.add_lagged`),
#: columns of ``floats`` after :data:`FLOATS`'s first ones, from :data:`LAG0`.
SHAPE_LAGS = tuple(f"_shape_lag_{j}" for j in range(2 * COMMIT_LAGS + 1))
LAG0 = len(FLOATS)
FLOATS += SHAPE_LAGS
#: Per-template flags updated in place: the columns of ``flags`` (K, len(FLAGS)), in this order.
FLAGS = ("_refused", "_engaged", "_misshaped", "_covered", "_at_hold_end", "_once", "_fresh",
         "_seated")
