"""Time alignment (MOP section 3.1.3): an action and a character motion of different lengths.

MOP normalises the durations of the performer's action X (T_x samples) and the character's motion
Y (T_y frames) so both have the same length. Here the follower's progress (0 at the action's
first sample, 1 at its last) is the shared time: the motion is played at the same fraction of
its own length, so no data is resampled unless asked for.
"""

from __future__ import annotations

import numpy as np


def progress_to_index(progress: float | np.ndarray, n_frames: int) -> float | np.ndarray:
    """Fractional frame index (0..n_frames-1) of a motion at ``progress`` (clipped to 0..1)."""
    if n_frames < 1:
        raise ValueError(f"a motion needs at least one frame, got {n_frames}")
    return np.clip(progress, 0.0, 1.0) * (n_frames - 1)


def index_to_progress(index: float | np.ndarray, n_samples: int) -> float | np.ndarray:
    """Progress (0..1) of a fractional sample index into a sequence of ``n_samples``."""
    if n_samples < 2:
        raise ValueError(f"progress needs at least two samples, got {n_samples}")
    return np.clip(np.asarray(index, dtype=float) / (n_samples - 1), 0.0, 1.0)


def sample_at_progress(frames: np.ndarray, progress: float) -> np.ndarray:
    """Linear interpolation of a motion ``frames`` (T_y, k) at ``progress`` (0..1): one frame (k,).

    Plain numbers only; angles or quaternions need their own interpolation (part of the clips).
    """
    y = np.asarray(frames, dtype=float)
    if y.ndim == 1:
        y = y[:, None]
    x = float(progress_to_index(progress, y.shape[0]))
    i = min(int(np.floor(x)), y.shape[0] - 1)
    j = min(i + 1, y.shape[0] - 1)
    a = x - i
    return (1.0 - a) * y[i] + a * y[j]


def resample_to_length(frames: np.ndarray, n: int) -> np.ndarray:
    """Resample a sequence (T, k) linearly to ``n`` samples with the same start and end (the
    paper's duration normalisation, for when equal lengths are wanted)."""
    y = np.asarray(frames, dtype=float)
    squeeze = y.ndim == 1
    if squeeze:
        y = y[:, None]
    if n < 1 or y.shape[0] < 1:
        raise ValueError(f"cannot resample {y.shape[0]} samples to {n}")
    if y.shape[0] == 1:
        out = np.repeat(y, n, axis=0)
    else:
        src = np.linspace(0.0, y.shape[0] - 1, n)
        base = np.arange(y.shape[0])
        out = np.stack([np.interp(src, base, y[:, j]) for j in range(y.shape[1])], axis=1)
    return out[:, 0] if squeeze else out
