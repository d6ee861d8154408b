"""The ranges of :class:`~behaviors.mop.follower.ActionFollower`'s parameters (see its
docstring for what each one is)."""

from __future__ import annotations

import math

from behaviors.mop.hmm import TemplateError


def check_ranges(*, sigma: float, window: int, memory: float, null_distance: float,
                 null_memory: float, onset: float, accept_distance: float, max_spread: float,
                 relative_floor: float, floor: float, scale_prior: float, hold_tolerance: float,
                 switch_margin: float, confirm: int, end: float, still_samples: int,
                 min_probability: float, tangent: float, coverage: float, shape_distance: float,
                 shape_accept: float, shape_memory: float, dwell: float | None,
                 share_radius: float, turn_limit: float, threshold: float) -> None:
    """Raise :class:`~behaviors.mop.hmm.TemplateError` naming the first parameter out of its
    range."""
    for name, v, ok in (("sigma", sigma, sigma > 0), ("window", window, window >= 1),
                        ("memory", memory, memory >= 1),
                        ("null_distance", null_distance, null_distance > 0),
                        ("null_memory", null_memory, null_memory >= 1),
                        ("onset", onset, onset >= 0),
                        ("accept_distance", accept_distance,
                         0 < accept_distance <= null_distance),
                        ("max_spread", max_spread, max_spread > 0),
                        ("relative_floor", relative_floor, relative_floor >= 0),
                        ("floor", floor, floor >= 0),
                        ("scale_prior", scale_prior, scale_prior > 0),
                        ("hold_tolerance", hold_tolerance, hold_tolerance >= 0),
                        ("switch_margin", switch_margin, switch_margin >= 0),
                        ("confirm", confirm, confirm >= 1), ("end", end, 0 < end <= 1),
                        ("still_samples", still_samples, still_samples >= 2),
                        ("min_probability", min_probability, 0 <= min_probability < 1),
                        ("tangent", tangent, tangent >= 0),
                        ("coverage", coverage, 0 <= coverage < 1),
                        ("shape_distance", shape_distance, shape_distance > 0),
                        ("shape_accept", shape_accept, 0 < shape_accept <= shape_distance),
                        ("shape_memory", shape_memory, shape_memory >= 1),
                        ("dwell", 0.0 if dwell is None else dwell,
                         dwell is None or 0 <= dwell < 1)):
        if not (math.isfinite(v) and ok):
            raise TemplateError(f"follower parameter {name} = {v} is out of range")
    if not (math.isfinite(share_radius) and share_radius >= 0):
        raise TemplateError(f"follower parameter share_radius = {share_radius} is out of range")
    if not turn_limit > 0:
        raise TemplateError(f"follower parameter turn_limit = {turn_limit} is out of range")
    if math.isnan(threshold) or threshold == -math.inf:
        raise TemplateError(f"follower parameter threshold = {threshold} is out of range")
