"""Fidelity of a generated reactor to its demonstration: the character figures side by side.

A demonstration shows a character reacting to one main path; the engine must keep that
character on main paths it never saw. :func:`figures` measures one pair of paths (main and
reactor poses on one time grid) and :func:`compare` sets a generation's figures beside its
demonstration's, with the thresholds a designer would notice:

- ``distance_w1_m``: Wasserstein-1 distance between the distance-to-main distributions (m);
- ``sectors_tv``: total variation between the occupancies of eight sectors of the reactor's
  bearing in the main's frame (0 = same, 1 = disjoint);
- ``speed_w1_mps``: Wasserstein-1 distance between per-step speed distributions (m/s); the
  threshold is 20% of the demonstration's mean speed;
- ``speed_still_mps`` / ``speed_moving_mps``: mean reactor speed while the main is still
  (under 0.02 m/s) and while it moves (over 0.05 m/s); their ratio is an event figure;
- ``facing``: share of steps looking within 45 degrees of the main (within 0.1);
- ``look_change_rad``: mean absolute per-step change of look (0.67-1.5x);
- ``saturation``: share of steps whose look change is at the turn limiter's limit (at most
  the demonstration's + 0.1, measured with the generator's limit on both);
- ``texture_rad``: RMS step-to-step change of movement direction while moving (0.67-1.5x);
- ``contact``: share of steps within 0.08 m of the main (an event figure);
- ``orbit_radps``: the reactor's own angular rate around the main (its velocity's tangential
  part over its distance, so a follower carried round by a turning main does not count),
  averaged over one second, absolute, while within 0.6 m (an event figure);
- ``edge_share``: share of steps the reactor spends within 0.1 m of a table edge (reported,
  no threshold; only where the table is known: a fleeing character that runs into the edges
  is caught there).

Event figures must stay within 30% of the demonstration's, or within a floor where the
demonstration's figure is near zero (a character that never touches has no 30% of it).

Times in seconds, positions in table metres, angles in radians.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tabletop.frames import wrap_angles

STILL_MPS = 0.02
MOVING_MPS = 0.05
FACING_RAD = math.pi / 4
CONTACT_M = 0.08
ORBIT_NEAR_M = 0.6
TEXTURE_MIN_MPS = 0.05
SECTORS = 8
EDGE_M = 0.1              # a reactor nearer than this to a table edge is at the edge
SATURATED = 0.95          # a step turning at least this share of the limit is saturated

# thresholds (issue: facing within 0.1; look change and texture 0.67-1.5x; speed W1 within
# 20% of the mean demonstrated speed; events within 30%; saturation at most demo + 0.1)
FACING_TOL = 0.1
RATIO_RANGE = (0.67, 1.5)
SPEED_W1_SHARE = 0.2
EVENT_SHARE = 0.3
SATURATION_TOL = 0.1
# floors of the event tolerances, for figures near zero
EVENT_FLOOR = {"contact": 0.02, "still_moving_ratio": 0.1, "orbit_radps": 0.1}


def w1(a: np.ndarray, b: np.ndarray, points: int = 512) -> float:
    """Wasserstein-1 distance between two 1-D samples (same unit as the samples)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.size == 0 or b.size == 0:
        return math.nan
    q = (np.arange(points) + 0.5) / points
    return float(np.mean(np.abs(np.quantile(a, q) - np.quantile(b, q))))


def span_speed(xy: np.ndarray, rate_hz: float, span_s: float) -> np.ndarray:
    """Speed (m/s) of each step of a path ``xy`` (n, 2), measured over ``span_s`` centred on
    the step (shorter at the ends): (n - 1,)."""
    n = xy.shape[0]
    h = max(1, int(round(0.5 * span_s * rate_hz)))
    i = np.arange(n - 1)
    a, b = np.maximum(i + 1 - h, 0), np.minimum(i + h, n - 1)
    d = xy[b] - xy[a]
    return np.hypot(d[:, 0], d[:, 1]) * rate_hz / (b - a)


def figures(main: np.ndarray, react: np.ndarray, rate_hz: float, max_turn_rate: float,
            table: tuple[float, float, float, float] | None = None) -> dict[str, Any]:
    """Figures of one main/reactor pair: ``main`` and ``react`` are (n, 3) x, y, look on one
    grid at ``rate_hz``; ``max_turn_rate`` (rad/s) is the look limiter's limit; ``table``
    (x0, y0, x1, y1) adds ``edge_share``. Returns scalar figures plus the samples that
    distributions are compared on (``_dist``, ``_speed``, ``_sector``)."""
    main, react = np.asarray(main, dtype=float), np.asarray(react, dtype=float)
    dt = 1.0 / rate_hz
    rel = react[:, :2] - main[:, :2]
    dist = np.hypot(rel[:, 0], rel[:, 1])
    step = np.diff(react[:, :2], axis=0)
    # speeds over 0.1 s (reactor) and 0.5 s (main, to decide still or moving), centred on each
    # step, so a hand's tremor does not count as travel; texture keeps the per-step steps
    speed = span_speed(react[:, :2], rate_hz, 0.1)
    msm = span_speed(main[:, :2], rate_hz, 0.5)
    still, moving = msm < STILL_MPS, msm > MOVING_MPS
    bearing = np.arctan2(-rel[:, 1], -rel[:, 0])            # from the reactor to the main
    facing = np.abs(wrap_angles(react[:, 2] - bearing)) < FACING_RAD
    dlook = np.abs(wrap_angles(np.diff(react[:, 2])))
    limit = max_turn_rate * dt
    heading = np.arctan2(step[:, 1], step[:, 0])
    turn = wrap_angles(np.diff(heading))
    ok = (speed[1:] > TEXTURE_MIN_MPS) & (speed[:-1] > TEXTURE_MIN_MPS)
    sector_angle = wrap_angles(np.arctan2(rel[:, 1], rel[:, 0]) - main[:, 2])
    sector = np.floor((sector_angle + math.pi) / (2 * math.pi) * SECTORS).astype(int) % SECTORS
    # the reactor's own angular rate around the main: (r x v_react) / |r|^2, so a follower
    # carried round by a turning main does not count, then averaged over one second
    r = 0.5 * (rel[1:] + rel[:-1])
    omega = (r[:, 0] * step[:, 1] - r[:, 1] * step[:, 0]) * rate_hz / np.maximum(
        np.einsum("ij,ij->i", r, r), 1e-6)
    s = max(1, int(round(rate_hz)))
    orbit = np.abs(np.convolve(omega, np.ones(s) / s, mode="valid"))
    near = np.convolve((dist[1:] < ORBIT_NEAR_M).astype(float), np.ones(s) / s,
                       mode="valid") > 0.999
    edge = math.nan
    if table is not None:
        x0, y0, x1, y1 = table
        room = np.minimum(np.minimum(react[:, 0] - x0, x1 - react[:, 0]),
                          np.minimum(react[:, 1] - y0, y1 - react[:, 1]))
        edge = float(np.mean(room < EDGE_M))
    v_still = float(np.mean(speed[still])) if still.any() else math.nan
    v_moving = float(np.mean(speed[moving])) if moving.any() else math.nan
    return {
        "distance_mean_m": float(dist.mean()),
        "speed_mean_mps": float(speed.mean()),
        "speed_still_mps": v_still,
        "speed_moving_mps": v_moving,
        "still_moving_ratio": v_still / v_moving if v_moving > 0 else math.nan,
        "facing": float(facing.mean()),
        "look_change_rad": float(dlook.mean()),
        "saturation": float(np.mean(dlook >= SATURATED * limit)),
        "texture_rad": float(np.sqrt(np.mean(turn[ok] ** 2))) if ok.any() else 0.0,
        "contact": float(np.mean(dist < CONTACT_M)),
        "orbit_radps": float(orbit[near].mean()) if near.any() else 0.0,
        "edge_share": edge,
        "_dist": dist, "_speed": speed,
        "_sector": np.bincount(sector, minlength=SECTORS) / sector.size,
    }


def _ratio_ok(gen: float, demo: float) -> bool:
    if demo <= 1e-9:
        return gen <= 1e-3
    return RATIO_RANGE[0] <= gen / demo <= RATIO_RANGE[1]


def _event_ok(name: str, gen: float, demo: float) -> bool:
    if not (math.isfinite(gen) and math.isfinite(demo)):
        return True        # no still main (or no motion) in one of them: nothing to compare
    return abs(gen - demo) <= max(EVENT_SHARE * abs(demo), EVENT_FLOOR[name])


def compare(demo: dict[str, Any], gen: dict[str, Any]) -> dict[str, Any]:
    """Generation figures beside the demonstration's, the distances between their
    distributions, and ``ok_*`` flags for every threshold (``ok``: all of them)."""
    row: dict[str, Any] = {}
    for key in ("distance_mean_m", "speed_mean_mps", "speed_still_mps", "speed_moving_mps",
                "still_moving_ratio", "facing", "look_change_rad", "saturation", "texture_rad",
                "contact", "orbit_radps", "edge_share"):
        row[f"demo_{key}"] = demo.get(key, math.nan)
        row[f"gen_{key}"] = gen.get(key, math.nan)
    row["distance_w1_m"] = w1(demo["_dist"], gen["_dist"])
    row["sectors_tv"] = float(0.5 * np.abs(demo["_sector"] - gen["_sector"]).sum())
    row["speed_w1_mps"] = w1(demo["_speed"], gen["_speed"])
    ok = {
        "facing": abs(gen["facing"] - demo["facing"]) <= FACING_TOL,
        "look_change": _ratio_ok(gen["look_change_rad"], demo["look_change_rad"]),
        "texture": _ratio_ok(gen["texture_rad"], demo["texture_rad"]),
        "speed": row["speed_w1_mps"] <= SPEED_W1_SHARE * demo["speed_mean_mps"],
        "contact": _event_ok("contact", gen["contact"], demo["contact"]),
        "still_moving": _event_ok("still_moving_ratio", gen["still_moving_ratio"],
                                  demo["still_moving_ratio"]),
        "orbit": _event_ok("orbit_radps", gen["orbit_radps"], demo["orbit_radps"]),
        "saturation": gen["saturation"] <= demo["saturation"] + SATURATION_TOL,
    }
    for k, v in ok.items():
        row[f"ok_{k}"] = bool(v)
    row["ok"] = all(ok.values())
    return row


def failures(row: dict[str, Any]) -> list[str]:
    """Names of the thresholds a compared row misses."""
    return [k[3:] for k, v in row.items() if k.startswith("ok_") and not v]


# the event thresholds and the figure each compares
EVENTS = {"contact": "contact", "still_moving": "still_moving_ratio", "orbit": "orbit_radps"}


def floor_only(row: dict[str, Any]) -> list[str]:
    """Event thresholds a compared row meets only through :data:`EVENT_FLOOR`: the generated
    figure is off the demonstration's by more than 30% of it but within the floor (where the
    demonstration's figure is under floor / 0.3: contact 0.067, still/moving and orbit 0.33)."""
    out = []
    for ok, key in EVENTS.items():
        gen, demo = row[f"gen_{key}"], row[f"demo_{key}"]
        if row[f"ok_{ok}"] and math.isfinite(gen) and math.isfinite(demo) \
                and abs(gen - demo) > EVENT_SHARE * abs(demo):
            out.append(ok)
    return out


def floor_only_table(table: dict[str, dict[str, dict[str, Any]]]) -> list[str]:
    """``behaviour:path:threshold`` of the event thresholds met only through their floor
    (:func:`floor_only`) in a {behaviour: {path: compared row}} table."""
    return [f"{name}:{path}:{k}" for name, paths in table.items()
            for path, row in paths.items() for k in floor_only(row)]


def tally(table: dict[str, dict[str, dict[str, Any]]]
          ) -> tuple[int, int, dict[str, int], int]:
    """Counts over a {behaviour: {path: compared row}} table: (pairs within every threshold,
    pairs, pairs within each threshold, thresholds met)."""
    passed = total = 0
    per_threshold: dict[str, int] = {}
    for paths in table.values():
        for row in paths.values():
            total += 1
            passed += int(row["ok"])
            for k, v in row.items():
                if k.startswith("ok_"):
                    per_threshold[k[3:]] = per_threshold.get(k[3:], 0) + int(v)
    return passed, total, per_threshold, sum(per_threshold.values())


def engine_misses(table: dict[str, dict[str, dict[str, Any]]],
                  reference: dict[str, dict[str, dict[str, Any]]]
                  ) -> dict[str, dict[str, list[str]]]:
    """{behaviour: {path: thresholds}} the generation misses where the designer's own
    character on the same path (``reference``, compared the same way) meets them: the misses
    of the engine, not of the path."""
    out: dict[str, dict[str, list[str]]] = {}
    for name, paths in table.items():
        for path, row in paths.items():
            own = reference[name][path]
            missed = [k for k in failures(row) if own[f"ok_{k}"]]
            if missed:
                out.setdefault(name, {})[path] = missed
    return out


def count(misses: dict[str, dict[str, list[str]]]) -> int:
    """The thresholds missed in a {behaviour: {path: thresholds}} table (:func:`engine_misses`)."""
    return sum(len(v) for paths in misses.values() for v in paths.values())


def main_on_grid(main: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Main poses (x, y, look) of a path ``main`` (n, 4) ``t, x, y, dir`` at times ``t``."""
    return np.column_stack([np.interp(t, main[:, 0], main[:, 1]),
                            np.interp(t, main[:, 0], main[:, 2]),
                            wrap_angles(np.interp(t, main[:, 0], np.unwrap(main[:, 3])))])


def generate(behavior: Any, main: np.ndarray,
             table: tuple[float, float, float, float]) -> np.ndarray:
    """Reactor rows (m, 4) ``t, x, y, look`` generated for a main path (n, 4), every step."""
    from behaviors.puppet_master.engine import Reactor
    reactor = Reactor(behavior, table, max_backlog=None)
    rows: list[tuple[float, float, float, float]] = []
    for t, x, y, d in np.asarray(main, dtype=float):
        rows.extend(reactor.advance(float(t), float(x), float(y), float(d)))
    return np.array(rows, dtype=float).reshape(-1, 4)


def demonstration_figures(behavior: Any,
                          table: tuple[float, float, float, float] | None = None
                          ) -> dict[str, Any]:
    """Figures of a trained behaviour's own demonstration (at its generation rate; ``table``:
    the table it was made on, for ``edge_share``)."""
    p = behavior.params
    return figures(behavior.main, behavior.react, p.rate_hz, behavior.turn_limit, table)


def evaluate(behavior: Any, main: np.ndarray, table: tuple[float, float, float, float],
             demo: dict[str, Any] | None = None) -> dict[str, Any]:
    """Generate for ``main`` and compare with the demonstration (see :func:`compare`)."""
    p = behavior.params
    rows = generate(behavior, main, table)
    gen = figures(main_on_grid(main, rows[:, 0]), rows[:, 1:], p.rate_hz, behavior.turn_limit,
                  table)
    return compare(demonstration_figures(behavior) if demo is None else demo, gen)


def pursue(behavior: Any, pursuer: Any, table: tuple[float, float, float, float]
           ) -> tuple[np.ndarray, np.ndarray]:
    """A reactor generated against a main hand that reacts to it (``pursuer``, fresh, e.g.
    visitors.Pursuer): each main sample is made from the reactor's pose after the steps of
    the samples before it. Returns the main path (n, 4) ``t, x, y, dir`` and the reactor rows
    (m, 4) ``t, x, y, look``."""
    from behaviors.puppet_master.engine import Reactor
    reactor = Reactor(behavior, table, max_backlog=None)
    main = np.empty((len(pursuer.times), 4))
    rows: list[tuple[float, float, float, float]] = []
    for i, t in enumerate(pursuer.times):
        pose = pursuer.first() if i == 0 else pursuer.step(i, main[i - 1, 1:4],
                                                             np.array(reactor.pose))
        main[i] = (float(t), *pose)
        rows.extend(reactor.advance(float(t), float(pose[0]), float(pose[1]), float(pose[2])))
    return main, np.array(rows, dtype=float).reshape(-1, 4)


def evaluate_pursuit(behavior: Any, pursuer: Any, table: tuple[float, float, float, float],
                     demo: dict[str, Any] | None = None) -> dict[str, Any]:
    """Generate against a main hand that goes after the reactor (:func:`pursue`) and compare
    with the demonstration (see :func:`compare`)."""
    p = behavior.params
    main, rows = pursue(behavior, pursuer, table)
    gen = figures(main_on_grid(main, rows[:, 0]), rows[:, 1:], p.rate_hz, behavior.turn_limit,
                  table)
    return compare(demonstration_figures(behavior) if demo is None else demo, gen)
