"""Puppet Master fidelity: every shipped behaviour on main paths it never saw, against its own
demonstration (behaviors/puppet_master/fidelity.py defines the figures and thresholds).

For each behaviour in behaviors/library and each unseen main path (a slow wanderer with pauses
at 30 Hz, a fast reversing hand at 60 Hz, loops and spins in place at 45 Hz; 40 s each), the
reactor is generated causally as it would be live and measured beside its demonstration:
distance-to-main W1, sector occupancy, speeds (all, main still, main moving), facing-the-main
share, per-step look change, turn-limiter saturation, direction-change texture, contact share
and orbit rate. Prints a table per behaviour, then one JSON line.

Beside each generation, the scripted designer's own character is played against the same
unseen path (:func:`designer_row`: the policy that made the demonstration, reacting to the new
main) and measured against the demonstration the same way. A threshold that the designer's own
character misses on a path is a figure of the situation, not of the engine: a demonstration
shows a character in the situations its main made, and a figure such as the share of time
spent facing the main depends on them (measured on seeds 0, 1, 2 with the former 60 s afraid
demonstration, see behaviors/puppet_master/chased.py: the afraid character's own
designer faced the main 78-94% of the time on the unseen paths, whose mains never chase it,
against 39% in the demonstration, whose main chased it half of the time; the generated afraid
character 53-76%). These are reported as ``designer.*`` figures and after the tables; they
do not count in ``thresholds_met``. ``engine_only_misses`` counts the thresholds the
generation misses where the designer's own character on the same path meets them: the misses
that are the engine's, not the path's (printed per behaviour and path for the first seed;
measured on seeds 0-5: 8 of the 44 misses on the open paths, 1 of the 1 on the pursuit).

The characters whose demonstration shows them chased (designers.CHASED: afraid) are also
generated against an unseen visitor going after them (``pursuit_50hz``: visitors.Pursuer, a
closed loop in which each main sample is made from where the reactor is now, chasing at
0.12-0.35 m/s about half of the time, pausing, pulling back and wandering otherwise), with
the designer's own character on its own closed loop beside it. This is the kind of path the
demonstration implies; the open paths stay as they are, and the pursuit figures are reported
apart (``pursuit.*``, ``seed<S>.pursuit.thresholds_met``, ``all_seeds.pursuit.*``), not in
``thresholds_met``. Measured on seeds 0-5 (8 thresholds per seed): the generation met 47 of
48 and the designer's own character 41, where on the open paths the designer's own afraid
character misses facing, speed, still/moving and orbit on every path of seed 0.

``--seeds 0,1,2`` measures on several sets of unseen paths (the path generators' seeds) and
adds the thresholds met per set and in total: a change of the generator moves every generated
path, and single borderline figures flip either way with it (measured: the same code met 96,
91 and 99 of 120 thresholds on seeds 0, 1 and 2), so a change is judged on several sets. The
figures of the first seed are reported in full, as with ``--seed``. How far the totals move
on their own: a look rule whose one parameter was set to 0.13, 0.15 and 0.17 m/s (a smooth
change of the same rule) met 592, 616 and 593 of 720 thresholds on seeds 0-5, against 601
without the rule, and 305 against 306 on seeds 0-2 alone at 0.15; a change worth less than
about 15 of 720 on six seeds cannot be told from the re-matching's chaos. The drift
correction's share (Params.relative_motion) scaled by 1 +- 0.001 and 1 +- 0.002, no rule
changed, met 655, 655, 657, 658 of 720 on seeds 0-5 (the engine's alone 20-22) where the
unperturbed step meets 666 (18), but 648 / 651 against 652 on seeds 8-13 (the engine's alone
31 / 23 against 30) and 110 / 109 against 109 on seed 7: a total reached by keeping what met
most on seeds 0-5 stands above its neighbours there, so a change is read against such a
perturbed cloud and on the held-out seeds. Per behaviour over those four runs on seeds 0-5
(misses, the engine's alone): lover 16-18 (5-7), bully 5-9 (4-6), playful friend 1-4 (1-4),
stalker 9-13 (4-6), afraid 23-28 (2-4); one behaviour's engine-only count moves by up to 3
with no change of its rules. With several seeds,
each behaviour's misses are also listed over every seed (:func:`behaviour_misses`:
``seed:path:threshold``, the engine's alone marked; ``all_seeds.<behaviour>.misses``), as the
first seed's tables show only that seed. Measured on seeds 0-5 (misses, of them the
engine's alone): lover 15 (2), bully 0 (0), playful friend 3 (3), stalker 5 (2), afraid 21
(1, most of them where its own designer misses too: the open paths never chase it).

``--perturb K`` measures that cloud itself (:func:`cloud`): the open paths of every seed
generated again K times with the drift correction's share scaled by 1 + d (d = +0.001,
-0.001, +0.002, -0.002, ...), and reports, per behaviour and in total, the misses and the
engine's alone of the unperturbed run and of each perturbed one (``cloud.*``, first the
unperturbed). A change is read against the spread of those lists on seeds 0-5 and on the
held-out seeds. Measured on seeds 0-5 / 8-13 with K = 4 (mean [least-most] of the five runs;
lover generated alone, tools outside the bench): the lover misses 16.8 [16-18] / 14.4
[13-15], the engine's alone 6.0 [5-7] / 5.0 [3-6]; the playful friend 2.2 [1-4] / 5.0 [4-6]
(all of them contact, both ways: 0.000-0.071 against 0.041, its designer 0.022-0.056).
On held-out seeds 300-311 with K = 6: met 1321-1333 (1331 unperturbed), the engine's alone
23-29 (23), its friend 0-4 (0; 0 / 3 / 1 / 2 / 0 / 2 / 4, and 4 / 4 at 1 +- 0.004): a single
run's friend there is no base to judge a change of it by.

What the engine's own misses are, measured on the 54 open paths and 18 pursuits of seeds 0-5,
8-13, 26-31 (7 / 16 / 16 open, 1 / 3 / 4 pursuit): event figures on both sides of their band
(contact 16, still/moving 16, orbit 5, speed 2 open; the friend's contact 3 over, 6 under; the
stalker's 5 over, 2 under), where the generation's mean is its designer's (friend contact 0.038
against 0.034, stalker fast 0.044 / 0.039, lover slow still/moving 0.52 / 0.53). A threshold
missed as often by the generation as by its designer on one kind of path still gives
engine-only misses where the two draws differ (stalker fast contact: 8 and 8 of 18 missed, 4
the engine's alone; generation.less_approach brings its mean to 0.036: the figures
there); counted as independent draws at each side's miss rate, 63 were expected,
47 seen. Missed clearly more often than by the designer: the playful friend's contact (9
against 1 of 54; the stalker's loops still/moving and orbit 4 / 3 against 1 / 0 of 18, its
still speed and orbit there a little under its designer's). The friend dips as often (15.4 /
15.7 dips under 0.12 m a path) and as deep (median least distance 0.089 m both, 38% / 37% under
0.08 m), but which of its dips reach 0.08 m varies from path to path as independent darts would
(5.8 +- 1.8 a path), where its designer's darts, timed by a 2-4 s clock and deepened by a slow
sway, vary less (5.8 +- 1.3); their stay under 0.08 m 10.6 +- 2.8 samples against 9.3 +- 1.7.
What the generation does not keep is the slow sway of its distance (period 4.8 s, longer than
the 1 s match window), which sets how deep a dart goes: the 1 s mean distance's autocorrelation
at 2.4 / 4.8 s is -0.46 / 0.42 in the demonstration, -0.42 / 0.29 for its designer on 24 unseen
paths of seeds 0-3, 8-11, -0.12 / 0.00 generated (its spread kept, 0.027 m both), so each dart
falls at a sway phase of its own. The sway's phase as a feature (the distance's slow mean) was
not followed by the match (autocorrelation at 4.8 s still about 0; friend misses up); the
steps since its last touch among its features (Behavior.circling, as the bully's charges) time
its darts as its designer's clock does (the figures, with and without, are in
behaviors/puppet_master/behavior.py, where Behavior takes its since feature). The friend's
darts that fall short on the loops paths: behaviors/puppet_master/step.py, where a place held
in the world takes its cap. The stalker's loops contact is its designer's: 0.008 mean on the 18
paths of seeds 0-5, 8-13, 26-31 for both, missed on 24 of 90 path runs (relative_motion x 1, 1
+- 0.001, 1 +- 0.002) against its designer's 25 (5 of the 18 paths), 22 of them without a
single touch, so its engine-only marks there are draws (seed 0: 0.000, its designer 0.0037, the
band from 0.002). Traced on seeds 0-5 (Python step), the match sits on moments under 0.08 m 3.3
/ 3.8 / 1.1% of the steps on the slow / fast / loops paths, the stalker is there 1.8 / 3.6 /
0.4%; at moments under 0.1 m it is 4.6-6.0 cm farther out than they are (closing on them at
most at their pace).

The event thresholds (contact, still/moving, orbit) hold within 30% of the demonstration's
figure or within a floor (fidelity.EVENT_FLOOR), whichever is wider; the floor is the wider one
wherever the demonstration's figure is under floor / 0.3 (contact 0.067, still/moving and orbit
0.33), which covers most shipped characters' contact. ``events_met_by_floor_only`` counts
the event thresholds met only through it (missed at 30% alone; named in
``events_met_by_floor_only_list``, per seed and over the seeds too; counted in the summary
line of ``python -m tabletop.examples --check`` as well). Measured on seed 0 (40 s
paths): 8 of the 45 event thresholds, 7 of them contact (the lover 0.000-0.001 against 0.008,
the playful friend 0.024 / 0.028 against 0.041, the stalker 0.009 / 0.040 against 0.022) and
the bully's loops orbit (0.371 against 0.275 rad/s); on seeds 0-5 39 of 270 (5-8 a seed), so
at 30% alone the 676 of 720 thresholds met there would be 637.

``--sequential`` adds sequential training beside two-puck demonstrations (:func:`sequential`,
tabletop.examples.sequential_comparison: the designer's main at 60 Hz, then its reaction on 60
Hz camera frames half a frame later against the playback seen a frame late, paired by
behaviors.puppet_master.sequential.pair_takes; two-puck demonstrations of the same character on
the same main on the reactor's camera frames, by the same designer's hand and by its second
hand at the same reaction time): per behaviour the thresholds each misses over the open paths
of every seed and its mean generated distance to the main (``sequential.<name>.<take>.misses``
/ ``.distance_m``), ``sequential.<name>.excess`` (the sequential misses beyond the two-puck
ones less the two hands' difference), ``.distance_excess_m`` (the sequential distance gap less
the two hands' difference) and ``.rule_misses``: what the test's rule
(tabletop.examples.sequential_misses: the character's allowance over two-puck, measured for
the test's 12 paths of 20 s, so on more paths a guide only) finds. Measured on seeds 0-5, 8-13,
26-31 (misses, sequential / two-puck / second hand; distance excess): lover 110 / 106 / 104,
-0.0 mm; bully 26 / 34 / 44, +3.4 mm; playful friend 4 / 7 / 8, -1.7 mm; stalker 62 / 37 / 50,
+1.3 mm; afraid 108 / 87 / 88, -2.9 mm (excess 12 and 20 misses for the stalker and the
afraid). Both figures are one main path's (the designer's shipped one), and one main path is one
draw: the stalker's designer draws no random choice, so its hands differ only in shake (on that
path two-puck 37-64 by hands 0-700, sequential 60-73), while on the same designer's other main
paths (seeds +1..+7) sequential and two-puck differ by -9 to +10 (means 50.1 / 48.1 with the
shipped path), and a two-puck demonstration whose reaction is one frame slower misses 68 on the
shipped path: that path's demonstration is sensitive to 17 ms of reaction, which the playback
seen a frame late adds (the study in behaviors/puppet_master/sequential.py). The afraid's
excess is its shipped path's too (two-puck / sequential on seeds +1..+3: 129 / 127, 105 / 101,
106 / 107), and the others differ as much by path (lover 65 / 58, 91 / 100, 49 / 66; bully 38 /
35, 35 / 37, 55 / 64; playful friend 12 / 15, 20 / 16, 13 / 12).

    .venv/bin/python bench/fidelity.py [--seconds 40] [--seed 0 | --seeds 0,1,2] [--perturb K]
                                       [--sequential]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.common import emit  # noqa: E402
from behaviors.puppet_master import fidelity  # noqa: E402
from behaviors.puppet_master.fidelity import engine_misses  # noqa: E402
from behaviors.puppet_master import designers  # noqa: E402
from tabletop.examples import (designer_table, fidelity_table,  # noqa: E402
                               print_report, pursuit_table, sequential_comparison,
                               sequential_misses)


def _seeds(text: str) -> list[int]:
    try:
        seeds = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"--seeds {text!r}: expected integers separated by "
                                         "commas, e.g. 0,1,2") from None
    if not seeds:
        raise argparse.ArgumentTypeError("--seeds: at least one seed")
    return seeds


def behaviour_misses(table: dict[str, dict[str, dict]],
                     engine: dict[str, dict[str, list[str]]], seed: int,
                     into: dict[str, list[str]]) -> None:
    """Adds each behaviour's misses on one seed's paths to ``into`` as ``seed:path:threshold``
    (with a trailing ``*`` where the miss is the engine's alone, see :func:`engine_misses`)."""
    for name, paths in table.items():
        out = into.setdefault(name, [])
        for path, row in paths.items():
            own = engine.get(name, {}).get(path, [])
            out.extend(f"{seed}:{path}:{k}{'*' if k in own else ''}"
                       for k in fidelity.failures(row))


PERTURBATIONS = (0.001, -0.001, 0.002, -0.002, 0.003, -0.003, 0.004, -0.004)


def cloud(runs: int, seeds: list[int], seconds: float,
          references: dict[int, dict[str, dict[str, dict]]]) -> dict[str, list[int]]:
    """The bench's own spread: for the first ``runs`` of PERTURBATIONS, the open paths of
    ``seeds`` generated with the drift correction's share scaled by 1 + d, against the
    designer ``references`` of each seed. Returns {key: [per run]}: ``thresholds_met``,
    ``engine_only_misses`` and each behaviour's ``<name>.misses`` and
    ``<name>.engine_only_misses`` (summed over the seeds)."""
    out: dict[str, list[int]] = {}
    for d in PERTURBATIONS[:runs]:
        met = engine_n = 0
        by_behaviour: dict[str, list[str]] = {}
        for seed in seeds:
            table = fidelity_table(seconds=seconds, seed=seed, perturb=d)
            met += fidelity.tally(table)[3]
            engine = engine_misses(table, references[seed])
            engine_n += fidelity.count(engine)
            behaviour_misses(table, engine, seed, by_behaviour)
        run = miss_counts(met, engine_n, by_behaviour)
        for k, v in run.items():
            out.setdefault(k, []).append(v)
    return out


def budgets() -> dict[str, object]:
    """The thresholds as behaviors/puppet_master/fidelity.py applies them."""
    return {"facing_abs_diff": fidelity.FACING_TOL, "look_change_ratio": list(fidelity.RATIO_RANGE),
            "texture_ratio": list(fidelity.RATIO_RANGE),
            "speed_w1_share_of_mean_demo_speed": fidelity.SPEED_W1_SHARE,
            "events_share": fidelity.EVENT_SHARE, "events_floor": dict(fidelity.EVENT_FLOOR),
            "saturation_over_demo": fidelity.SATURATION_TOL}


def miss_counts(met: int, engine_n: int, by_behaviour: dict[str, list[str]]) -> dict[str, int]:
    """``thresholds_met``, ``engine_only_misses`` and each behaviour's ``<name>.misses`` and
    ``<name>.engine_only_misses`` from its :func:`behaviour_misses` list."""
    out = {"thresholds_met": met, "engine_only_misses": engine_n}
    for name, missed in by_behaviour.items():
        out[f"{name}.misses"] = len(missed)
        out[f"{name}.engine_only_misses"] = sum(m.endswith("*") for m in missed)
    return out


def sequential(seeds: list[int], seconds: float) -> dict[str, object]:
    """Sequential training beside two-puck demonstrations of each shipped character on the
    open paths of ``seeds`` (see the module doc): ``sequential.<name>.<take>.misses`` and
    ``.distance_m`` for take sequential, two_puck and second_hand,
    ``sequential.<name>.excess`` (misses beyond two-puck's and the two hands' difference),
    ``.distance_excess_m`` (the distance gap beyond the two hands' difference) and
    ``.rule_misses`` (tabletop.examples.sequential_misses: the test's rule, allowances
    included)."""
    out: dict[str, object] = {}
    for name in designers.PERSONALITIES:
        figures = sequential_comparison(name, tuple(seeds), seconds)
        for take, (missed, distance) in figures.items():
            out[f"sequential.{name}.{take}.misses"] = missed
            out[f"sequential.{name}.{take}.distance_m"] = round(distance, 4)
        (seq, seq_d), (two, two_d), (other, other_d) = (
            figures[k] for k in ("sequential", "two_puck", "second_hand"))
        out[f"sequential.{name}.excess"] = seq - two - abs(two - other)
        out[f"sequential.{name}.distance_excess_m"] = round(
            abs(seq_d - two_d) - abs(two_d - other_d), 4)
        out[f"sequential.{name}.rule_misses"] = sequential_misses(name, figures)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=40.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--seeds", type=_seeds, default=None, metavar="S[,S...]",
                    help="several sets of unseen paths (overrides --seed)")
    ap.add_argument("--perturb", type=int, default=0, metavar="K",
                    help=f"also K runs (at most {len(PERTURBATIONS)}) with the drift "
                         "correction's share scaled by 1 + 0.001, 1 - 0.001, ...: the "
                         "spread a change is read against")
    ap.add_argument("--sequential", action="store_true",
                    help="also sequential training beside two-puck demonstrations")
    args = ap.parse_args()
    if not args.seconds > 0:
        ap.error(f"--seconds {args.seconds}: must be > 0")
    if not 0 <= args.perturb <= len(PERTURBATIONS):
        ap.error(f"--perturb {args.perturb}: must be from 0 to {len(PERTURBATIONS)}")
    seeds = args.seeds or [args.seed]
    t0 = time.perf_counter()
    figures: dict[str, object] = {}
    met_all = total_all = ref_all = 0
    pursuit_all = pursuit_ref_all = engine_all = pursuit_engine_all = floored_all = 0
    by_behaviour: dict[str, list[str]] = {}
    references: dict[int, dict[str, dict[str, dict]]] = {}
    for n, seed in enumerate(seeds):
        table = fidelity_table(seconds=args.seconds, seed=seed)
        passed, total, per_threshold, met = fidelity.tally(table)
        met_all += met
        total_all += total * len(per_threshold)
        reference = references[seed] = designer_table(args.seconds, seed)
        ref_met = fidelity.tally(reference)[3]
        ref_all += ref_met
        pursuit = pursuit_table(seconds=args.seconds, seed=seed)
        pursuit_ref = designer_table(args.seconds, seed, pursuit=True)
        p_met, p_ref_met = fidelity.tally(pursuit)[3], fidelity.tally(pursuit_ref)[3]
        pursuit_all += p_met
        pursuit_ref_all += p_ref_met
        engine, p_engine = engine_misses(table, reference), engine_misses(pursuit, pursuit_ref)
        engine_all += fidelity.count(engine)
        floored = fidelity.floor_only_table(table)
        floored_all += len(floored)
        behaviour_misses(table, engine, seed, by_behaviour)
        pursuit_engine_all += fidelity.count(p_engine)
        if len(seeds) > 1:
            figures[f"seed{seed}.thresholds_met"] = met
            figures[f"seed{seed}.designer.thresholds_met"] = ref_met
            figures[f"seed{seed}.pursuit.thresholds_met"] = p_met
            figures[f"seed{seed}.pursuit.designer.thresholds_met"] = p_ref_met
            figures[f"seed{seed}.engine_only_misses"] = fidelity.count(engine)
            figures[f"seed{seed}.events_met_by_floor_only"] = len(floored)
            figures[f"seed{seed}.pursuit.engine_only_misses"] = fidelity.count(p_engine)
            for name, paths in pursuit.items():      # time at a table edge (no threshold)
                for path, row in paths.items():
                    figures[f"seed{seed}.pursuit.{name}.gen_edge_share"] = row["gen_edge_share"]
                    figures[f"seed{seed}.pursuit.{name}.designer_edge_share"] = \
                        pursuit_ref[name][path]["gen_edge_share"]
        if n:
            continue
        print_report(table, pursuit, reference, pursuit_ref)
        for prefix, ref in (("designer", reference), ("pursuit.designer", pursuit_ref)):
            for name, paths in ref.items():
                for path, row in paths.items():
                    figures[f"{prefix}.{name}.{path}.misses"] = ",".join(fidelity.failures(row))
        for k, v in fidelity.tally(reference)[2].items():
            figures[f"designer.pairs_within_{k}"] = v
        figures["designer.thresholds_met"] = ref_met
        for prefix, tab in (("", table), ("pursuit.", pursuit)):
            for name, paths in tab.items():
                for path, row in paths.items():
                    for k, v in row.items():
                        figures[f"{prefix}{name}.{path}.{k}"] = v
        figures["pairs_within_every_threshold"] = passed
        figures["pairs_total"] = total
        for k, v in per_threshold.items():
            figures[f"pairs_within_{k}"] = v
        figures["thresholds_met"] = met
        figures["thresholds_total"] = total * len(per_threshold)
        figures["pursuit.thresholds_met"] = p_met
        figures["pursuit.designer.thresholds_met"] = p_ref_met
        figures["engine_only_misses"] = fidelity.count(engine)
        figures["pursuit.engine_only_misses"] = fidelity.count(p_engine)
        # met at the floor, missed at 30% of the demonstration's figure alone
        print(f"event thresholds met only through their floor: {len(floored)} "
              f"({' '.join(floored) or '-'})")
        figures["events_met_by_floor_only"] = len(floored)
        figures["events_met_by_floor_only_list"] = " ".join(floored)
        figures["pursuit.thresholds_total"] = fidelity.tally(pursuit)[1] * len(per_threshold)
        figures["seed"] = seed
    print("misses per behaviour over the seeds (seed:path:threshold, * the engine's alone):")
    for name, missed in by_behaviour.items():
        alone = sum(m.endswith("*") for m in missed)
        print(f"  {name:18s}{len(missed):3d} ({alone} the engine's): {' '.join(missed)}")
        figures[f"all_seeds.{name}.misses"] = len(missed)
        figures[f"all_seeds.{name}.engine_only_misses"] = alone
        figures[f"all_seeds.{name}.missed"] = " ".join(missed)
    if len(seeds) > 1:
        figures["seeds"] = seeds
        figures["all_seeds.thresholds_met"] = met_all
        figures["all_seeds.designer.thresholds_met"] = ref_all
        figures["all_seeds.thresholds_total"] = total_all
        figures["all_seeds.pursuit.thresholds_met"] = pursuit_all
        figures["all_seeds.pursuit.designer.thresholds_met"] = pursuit_ref_all
        figures["all_seeds.engine_only_misses"] = engine_all
        figures["all_seeds.pursuit.engine_only_misses"] = pursuit_engine_all
        figures["all_seeds.events_met_by_floor_only"] = floored_all
    if args.perturb:
        spread = cloud(args.perturb, seeds, args.seconds, references)
        unperturbed = miss_counts(met_all, engine_all, by_behaviour)
        print(f"the bench's own spread ({args.perturb} perturbed runs; unperturbed first):")
        for k, v in spread.items():
            runs = [unperturbed[k], *v]
            figures[f"cloud.{k}"] = runs
            print(f"  {k:34s} {' '.join(map(str, runs))}   mean {np.mean(runs):.1f}")
    if args.sequential:
        seq = sequential(seeds, args.seconds)
        print("sequential training beside two-puck (misses, then mean distance m: sequential / "
              "two-puck / second hand; what the rule misses):")
        for name in designers.PERSONALITIES:
            takes = ("sequential", "two_puck", "second_hand")
            print(f"  {name:18s}" + " / ".join(str(seq[f"sequential.{name}.{k}.misses"])
                                               for k in takes) + "   " + " / ".join(
                f"{seq[f'sequential.{name}.{k}.distance_m']:.4f}" for k in takes)
                + "   " + ("; ".join(seq[f"sequential.{name}.rule_misses"]) or "-"))
        figures.update(seq)
    figures["seconds_per_path"] = args.seconds
    figures["run_s"] = time.perf_counter() - t0
    emit("fidelity", figures, budgets())


if __name__ == "__main__":
    main()
