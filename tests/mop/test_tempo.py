"""The followed state's tempo against the input's (:mod:`behaviors.mop.tempo`), on unrelated
motions of ``bench/follow_quality.py``: a new action is not taken at a crawl, and an action
followed at a crawl stops driving, the gestures themselves as valid as without."""

import numpy as np

from bench.follow_quality import puck_follower, run, true_metrics
from bench.motions import performance, unrelated_motions


def _crawl_shares(gestures):
    """Valid share of the triangle and the wander (0.7, 1.0, 1.4x) with the six gestures loaded."""
    rng = np.random.default_rng(11)
    f = puck_follower(gestures)
    paths = unrelated_motions(rng, gestures)
    out = {}
    for name in ("triangle", "wander"):
        shares = [np.mean([s.valid for s in run(f, performance(rng, paths[name], scale)[0])])
                  for scale in (0.7, 1.0, 1.4)]
        out[name] = float(np.mean(shares))
    return out


def test_a_new_action_is_not_taken_at_a_crawl(gestures, monkeypatch):
    # a template whose followed state crawls while the input sweeps on is not taken
    # (tempo.slow_take): the triangle's stroke held in a template's turn, the wander hovering.
    # Measured: triangle 0.089 (0.172 without), wander 0.028 (0.053); nothing vetoed as an
    # overrun (overrun.overruns takes these ticks too)
    from behaviors.mop import follower_validity, tempo, validity

    monkeypatch.setattr(follower_validity.Validity, "_overruns",
                        lambda self, k, g, x, progress: False)
    now = _crawl_shares(gestures)
    monkeypatch.setattr(tempo, "LEAST_TEMPO", 0.0)
    monkeypatch.setattr(validity, "LEAST_TEMPO", 0.0)
    plain = _crawl_shares(gestures)
    assert now["triangle"] <= 0.1 and now["triangle"] <= plain["triangle"] - 0.07, (now, plain)
    assert now["wander"] <= plain["wander"] - 0.02, (now, plain)


def _stretch_shares(gestures) -> tuple[float, float, float]:
    """The triangle's and the diagonal's valid share (0.7, 1.0, 1.4x) and the six gestures'
    valid share after 30% (0.7, 1.4x), the six gestures loaded, over three seeds; shared starts
    off (``share_radius`` 0): the rules' own effect."""
    tri, diag, true = [], [], []
    for seed in (3, 11, 13):
        rng = np.random.default_rng(seed)
        f = puck_follower(gestures, share_radius=0.0)
        paths = unrelated_motions(rng, gestures)
        for out, name in ((diag, "diagonal"), (tri, "triangle")):
            out += [np.mean([s.valid for s in run(f, performance(rng, paths[name], scale)[0])])
                    for scale in (0.7, 1.0, 1.4)]
        for name, tpl in gestures.items():
            for scale in (0.7, 1.4):
                x, prog = performance(rng, tpl, scale)
                true.append(true_metrics(run(f, x), name, prog)["valid_after30"])
    return float(np.mean(tri)), float(np.mean(diag)), float(np.mean(true))


def test_an_action_followed_at_a_crawl_stops_driving(gestures, monkeypatch):
    # a taken action whose followed state crawls for six samples in a row while the input sweeps
    # on is a template stretched over a path not its own (tempo.crawls): the triangle's
    # stroke along the line, a diagonal on the circle's chord. Measured: triangle 0.062 (0.076
    # without), diagonal 0.170 (0.173); the gestures themselves 0.824 (0.825) (before the sizes
    # at reversals, invariance.REVERSAL_FIT: 0.087 (0.106), 0.170 (0.173), 0.821 (0.821); before
    # invariance.ALONG and validity.unjudged: 0.098 (0.130), 0.217 (0.226), 0.816 (0.814))
    from behaviors.mop import tempo

    now = _stretch_shares(gestures)
    monkeypatch.setattr(tempo, "CRAWL_SAMPLES", 0)
    plain = _stretch_shares(gestures)
    assert now[0] <= plain[0] - 0.01 and now[1] <= plain[1], (now, plain)
    assert now[2] >= plain[2] - 0.005, (now, plain)
