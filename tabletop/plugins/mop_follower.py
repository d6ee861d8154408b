"""The ``follower`` options of engine ``mop`` (:mod:`tabletop.plugins.mop`'s schema): the
parameters of MOP's follower (:class:`behaviors.mop.follower.ActionFollower`) as a config gives
them, each with its default, unit and bounds."""

from __future__ import annotations

from tabletop.plugins.mop_library import WINDOW_RANGE
from tabletop.schema import ListOf, Number, Range, Record, Str

FOLLOWER = Record({
    "sigma": Number(0.2, lo=1e-3, hi=100.0),
    "window": Number(15, integer=True, lo=WINDOW_RANGE[0], hi=WINDOW_RANGE[1]),
    "transitions": ListOf(Number(lo=0.0), default=[0.3, 0.35, 0.25, 0.1], min_len=1),
    "backward": Number(0.1, lo=0.0),
    "restart": Number(1e-4, lo=0.0, hi=0.5),
    "memory": Number(20.0, lo=1.0, doc="samples: forgetting of the evidence (probabilities)"),
    "null_distance": Number(1.8, lo=0.01,
                            doc="sigmas: farther from the best template is no action"),
    "null_memory": Number(16, lo=1.0, doc="samples: forgetting of that distance"),
    "onset": Number(0.5, lo=0.0, doc="sigmas: an action drives its character once the "
                 "performance has left the action's start by this much"),
    "accept_distance": Number(1.2, lo=0.01, doc="sigmas: a refused action is accepted again "
                              "once nearer than this (at most null_distance)"),
    "invariance": Str("auto", choices=("auto", "scale", "offset", "none"),
                      doc="follow gestures of any size (scale) or place (offset) from where they "
                          "begin; auto: scale for puck and touch inputs, none for streams"),
    "tangent": Number(0.0, lo=0.0, hi=10.0, doc="weight of the direction of motion (puck and "
                      "touch inputs): tells a raise from its return, a gesture from its mirror"),
    "scale_range": Range(Number(lo=0.05, hi=20.0), default=[0.55, 1.8], contains=1.0,
                         doc="smallest and largest size of a performance, x the recorded"),
    "switch_margin": Number(1.0, lo=0.0,
                            doc="nats: another action takes over once this much likelier"),
    "confirm": Number(2, integer=True, lo=1, hi=100,
                      doc="samples a match must last to drive (one that alone puts a new action "
                          "far ahead in shape drives at once)"),
    "hold_tolerance": Number(0.02, lo=0.0, hi=1.0,
                             doc="a template's held stretch (within this of its spread) may last "
                                 "any time"),
    "max_spread": Number(0.15, lo=1e-3, hi=1.0),
    "relative_floor": Number(0.05, lo=0.0, hi=1.0),
})
