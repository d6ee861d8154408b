"""Helpers of the MOP engine tests beyond :mod:`tabletop.plugins.mop_table`."""

from typing import TYPE_CHECKING, Callable

import numpy as np

if TYPE_CHECKING:
    from behaviors.mop.group import FollowerGroup


def widened_mirrored(seed: int, name: str, scale: float) -> np.ndarray:
    """The mirrored template ``name`` at ``scale`` as ``bench/follow_widened.py`` draws it for
    ``seed`` (the draws before it made and dropped)."""
    from bench.motions import (MOCAP, gesture_templates, mocap_templates, performance,
                               unrelated_motions)
    templates = {**gesture_templates(), **mocap_templates(joints=MOCAP)}
    rng = np.random.default_rng(seed)
    for key, path in unrelated_motions(rng, templates).items():
        if key.startswith("mirrored_"):
            for s in (0.7, 1.0, 1.4):
                x = performance(rng, path, s)[0]
                if (key, s) == (f"mirrored_{name}", scale):
                    return x
    raise KeyError(name)


def unrelated_at_1x(templates: dict[str, np.ndarray], name: str, seed: int) -> np.ndarray:
    """The unrelated motion ``name`` against ``templates`` performed at 1x as the bench draws it
    for ``seed`` (its 0.7x draw made and dropped first)."""
    from bench.motions import performance, unrelated_motions
    rng = np.random.default_rng(seed)
    path = unrelated_motions(rng, templates)[name]
    performance(rng, path, 0.7)
    return performance(rng, path, 1.0)[0]


def held_out_draw(seed: int, want: str, want_scale: float, joints=None):
    """The held-out templates and the sized performance of ``want`` at ``want_scale`` that
    ``bench/follow_seeds.py`` draws with ``seed`` (its sized section's draws, in order; with
    ``joints=MOCAP`` and seed 13 ``bench/follow_quality.py``'s tuned ones)."""
    from bench.motions import MOCAP_HELD_OUT, gesture_templates, mocap_templates, performance
    templates = {**gesture_templates(),
                 **mocap_templates(joints=MOCAP_HELD_OUT if joints is None else joints)}
    rng = np.random.default_rng(seed)
    for name, tpl in templates.items():
        for scale in (0.6, 0.7, 0.85, 1.0, 1.2, 1.4, 1.5):
            pause = float(rng.uniform(0.3, 1.0)) if rng.uniform() < 0.3 else 0.0
            x, prog = performance(rng, tpl, scale, pause_s=pause)
            if name == want and scale == want_scale:
                return templates, x, prog
    raise KeyError(want)


def held_out_valid(seed: int, want: str, want_scale: float) -> float:
    """Share of the samples after 30% of :func:`held_out_draw`'s performance in which the puck
    follower of its templates drives ``want`` (``valid_after30``)."""
    from bench.follow_quality import puck_follower, run, true_metrics
    templates, x, prog = held_out_draw(seed, want, want_scale)
    return true_metrics(run(puck_follower(templates), x), want, prog)["valid_after30"]


def held_out_group_valid(seed: int, want: str, want_scale: float) -> int:
    """Valid samples of :func:`held_out_draw`'s performance stepped by a group of one puck
    follower, equal at every tick to a follower alone (:func:`group_beside_alone`)."""
    from bench.follow_quality import puck_follower
    templates, x, _ = held_out_draw(seed, want, want_scale)
    return group_beside_alone(lambda: puck_follower(templates), [x])[0]


def held_out_twenty(seed: int, nth: int) -> tuple[dict, np.ndarray, list, np.ndarray]:
    """The held-out twenty templates and ``bench/follow_seeds.py``'s seed ``seed``, its
    ``nth`` (from 1) sequence of twenty back to back: samples, truth, true progress."""
    from bench.follow_quality import holds, sized
    from bench.motions import MOCAP_HELD_OUT, back_to_back, gesture_templates, mocap_templates
    gestures = gesture_templates()
    templates = {**gestures, **mocap_templates(joints=MOCAP_HELD_OUT)}
    rng = np.random.default_rng(seed)
    sized(lambda t: None, templates, rng)   # the draws of the sections before the sequences
    holds(lambda t: None, gestures, rng)
    for _ in range(8):
        back_to_back(rng, gestures, 4)
    for _ in range(nth):
        x, truth, prog, _ = back_to_back(rng, templates, 4)
    return templates, x, truth, prog


def group_beside_alone(make: Callable, streams: list[np.ndarray]) -> list[int]:
    """Each of ``streams`` stepped by a member of one ``FollowerGroup`` (of ``make()``
    followers) and by a follower of its own beside it: every state equal (valid, best, progress
    to 1e-12) at every tick; returns each stream's valid ticks in the group."""
    import math

    from behaviors.mop.group import FollowerGroup
    alone = [make() for _ in streams]
    group = FollowerGroup([make() for _ in streams])
    valid = [0] * len(streams)
    for t in range(len(streams[0])):
        together = group.step([s[t] for s in streams])
        for j, (f, s, g) in enumerate(zip(alone, streams, together)):
            a = f.step(s[t])
            assert (a.valid, a.best) == (g.valid, g.best), t
            assert math.isclose(a.progress, g.progress, rel_tol=1e-12, abs_tol=1e-12), t
            valid[j] += g.valid
    return valid


def group_valid(make: Callable, streams: list[np.ndarray]) -> int:
    """Valid states of ``streams`` (as long as the shortest) stepped by one ``FollowerGroup`` of
    ``make()`` followers, one member each: each member's states are its follower's alone
    (:func:`group_beside_alone`)."""
    from behaviors.mop.group import FollowerGroup
    group = FollowerGroup([make() for _ in streams])
    return sum(s.valid for t in range(min(len(s) for s in streams))
               for s in group.step([s[t] for s in streams]))


def solo(follower) -> "FollowerGroup":
    """``follower`` as the one member of a ``FollowerGroup``: the compiled form the installation
    runs (tabletop/plugins/mop.py), equal to the follower alone at every tick
    (tests/mop/test_group.py) at about a sixth of its CPU a step (0.24 against 1.46 ms, the six
    gestures loaded). Not for a run whose rule is switched off by patching a constant the
    group's kernels compile in (most of validity's and tempo's, a patched Validity method):
    those keep to the follower. Constants read where the follower or the group is built
    (invariance.REACH_BOUND, REJUDGE, REVERSAL_FIT, coverage.OBSERVER, EARLY_FIT, LATE_FIT,
    LATE_UNTIL, shape_lead.TAKE_FIT, take_rule.TAKE_SIZES, validity.CARRY_FIRST,
    UNJUDGED_AT_REST, UNWEIGHED_AT_REST, REST_BEHIND, TAKEN_PERFORMED, RESTED_LIFTS,
    tempo.CRAWL_SAMPLES and CRAWL_HOVERS, spotting.TEMPO_END_FROM, gesture_end.ARRIVE_RADIUS:
    patch them before the group is built) and take_rule.TAKE_MISFIT2, threshold.CARRY_LEAD,
    shape_lead.LEAD and bends' (read at each step) reach both."""
    from behaviors.mop.group import FollowerGroup
    return FollowerGroup([follower])


def run(follower, x: np.ndarray) -> list:
    """``bench.follow_quality.run`` (the follower reset, then each sample of ``x`` stepped) for a
    follower or a group of one (:func:`solo`): each tick's state."""
    from bench.follow_quality import run as run_alone
    from behaviors.mop.group import FollowerGroup
    if not isinstance(follower, FollowerGroup):
        return run_alone(follower, x)
    follower.reset()
    return [follower.step([s])[0] for s in x]


def refused(tmp_path, mutate, *words: str, error: type = None) -> None:
    """The designer config (:func:`tabletop.plugins.mop_table.designer_config`) changed by
    ``mutate`` (given its engine) is refused at build with ``error`` (a ConfigError by default)
    whose message holds every one of ``words``."""
    import copy

    import pytest

    from tabletop.plugins.mop_table import build, designer_config
    from tabletop.schema import ConfigError
    data = copy.deepcopy(designer_config(tmp_path))
    mutate(data["engines"][0])
    with pytest.raises(error or ConfigError) as exc:
        build(data, tmp_path)
    for w in words:
        assert w in str(exc.value), str(exc.value)


def chain(rng: np.random.Generator, gestures: dict, order: list,
          size=lambda: 1.0) -> tuple[np.ndarray, list, np.ndarray]:
    """``order``'s gestures back to back (time-warped, each at ``size()``, starting where the
    last ended) after half a second still, with tracking jitter: samples, the true gesture per
    tick (None while still) and its true progress (NaN while still)."""
    from bench.motions import at_phase, phase_of
    parts, truth, prog, at = [], [], [], np.zeros(2)
    for g in order:
        phase, p = phase_of(rng, len(gestures[g]))
        parts.append(size() * at_phase(gestures[g], phase) + at)
        at = parts[-1][-1].copy()
        truth += [g] * len(p)
        prog.append(p[:, 0])
    x = (np.concatenate([np.zeros((15, 2))] + parts)
         + rng.normal(0, 0.0007, (15 + len(truth), 2)))
    return x, [None] * 15 + truth, np.concatenate([np.full(15, np.nan)] + prog)
