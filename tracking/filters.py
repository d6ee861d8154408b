"""The One Euro filter (Casiez, Roussel and Vogel, CHI 2012): an adaptive low-pass filter whose
cutoff rises with speed, so a still puck is still and a moving one does not lag.

    cutoff = min_cutoff + beta * |speed|,   speed low-passed at d_cutoff

Parameters are in the units of the signal: ``min_cutoff`` and ``d_cutoff`` in Hz, ``beta`` in
1 / (signal unit) (per metre for positions in metres, per radian for angles). A beta tuned in
pixels is wrong in metres: :func:`scale_beta` converts. The filter works on vectors (one row per
signal, e.g. x and y of a puck) and on stacks of them (one row per puck) in one call; the speed
of a vector signal is its Euclidean norm, so the filter is the same in every direction.
"""

from __future__ import annotations

import math

import numpy as np


def smoothing_factor(cutoff_hz: np.ndarray | float, dt: np.ndarray | float) -> np.ndarray:
    """Exponential smoothing factor alpha of a first-order low-pass at ``cutoff_hz`` for a step
    of ``dt`` seconds: alpha = 1 / (1 + tau / dt), tau = 1 / (2 pi cutoff)."""
    tau = 1.0 / (2.0 * math.pi * np.asarray(cutoff_hz, float))
    return 1.0 / (1.0 + tau / np.maximum(np.asarray(dt, float), 1e-9))


def one_euro_step(x: np.ndarray, x_prev: np.ndarray, dx_prev: np.ndarray, dt: np.ndarray | float,
                  min_cutoff: float, beta: float, d_cutoff: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """One step of the One Euro filter on rows of vectors.

    ``x``, ``x_prev`` (filtered), ``dx_prev`` (filtered derivative): arrays (..., D); ``dt``:
    seconds since the previous sample (scalar or (...)). Returns the filtered value and the
    filtered derivative (units per second).
    """
    x = np.asarray(x, float)
    dt_arr = np.maximum(np.asarray(dt, float), 1e-9)
    dxr = (x - x_prev) / dt_arr[..., None]
    dx = dx_prev + smoothing_factor(d_cutoff, dt_arr)[..., None] * (dxr - dx_prev)
    speed = np.linalg.norm(dx, axis=-1)
    a = smoothing_factor(min_cutoff + beta * speed, dt_arr)[..., None]
    return x_prev + a * (x - x_prev), dx


def one_euro_floats(x: list[float], value: list[float], derivative: list[float], dt: float,
                    min_cutoff: float, beta: float, d_cutoff: float
                    ) -> tuple[list[float], list[float]]:
    """:func:`one_euro_step` for one short vector in plain floats (a puck's x, y or its
    heading), where numpy's per-call overhead would dominate. Returns (value, derivative)."""
    a_d = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * d_cutoff * dt))
    d = [di + a_d * ((xi - vi) / dt - di) for xi, vi, di in zip(x, value, derivative)]
    speed = math.sqrt(sum(di * di for di in d))
    a = 1.0 / (1.0 + 1.0 / (2.0 * math.pi * (min_cutoff + beta * speed) * dt))
    return [vi + a * (xi - vi) for xi, vi in zip(x, value)], d


def scale_beta(beta: float, units_per_metre: float) -> float:
    """A beta given per metre, expressed for a signal in other units (e.g. pixels): the cutoff
    ``beta * speed`` must stay the same, and speeds scale by ``units_per_metre``."""
    return beta / units_per_metre


class OneEuroFilter:
    """A One Euro filter for one D-dimensional signal (or a stack of them, shape (..., D)).

    ``filter(x, t)`` returns the filtered value; the first sample passes through unchanged.
    ``reset(x, t)`` restarts from ``x``. ``derivative`` is the filtered rate of change (units/s).
    """

    def __init__(self, min_cutoff: float = 1.0, beta: float = 0.0, d_cutoff: float = 1.0) -> None:
        if min_cutoff <= 0 or d_cutoff <= 0 or beta < 0:
            raise ValueError("One Euro: min_cutoff and d_cutoff must be > 0 and beta >= 0")
        self.min_cutoff, self.beta, self.d_cutoff = float(min_cutoff), float(beta), float(d_cutoff)
        self.value: np.ndarray | None = None
        self.derivative: np.ndarray | None = None
        self.t: float | None = None

    def reset(self, x: np.ndarray, t: float) -> np.ndarray:
        """Restart at ``x`` (time ``t`` s) with zero derivative."""
        self.value = np.array(x, float)
        self.derivative = np.zeros_like(self.value)
        self.t = float(t)
        return self.value.copy()

    def filter(self, x: np.ndarray, t: float) -> np.ndarray:
        """Filter the sample ``x`` taken at time ``t`` (seconds); a sample not later than the
        previous one restarts nothing and returns the current value."""
        if self.value is None or self.t is None or self.derivative is None:
            return self.reset(x, t)
        dt = float(t) - self.t
        if dt <= 0.0:
            return self.value.copy()
        if self.value.ndim == 1 and self.value.size <= 4:
            self._filter_small(np.asarray(x, float), dt)
        else:
            self.value, self.derivative = one_euro_step(np.asarray(x, float), self.value,
                                                        self.derivative, dt, self.min_cutoff,
                                                        self.beta, self.d_cutoff)
        self.t = float(t)
        return self.value.copy()

    def _filter_small(self, x: np.ndarray, dt: float) -> None:
        v, d = one_euro_floats(x.tolist(), self.value.tolist(), self.derivative.tolist(), dt,
                               self.min_cutoff, self.beta, self.d_cutoff)
        self.value, self.derivative = np.array(v), np.array(d)
