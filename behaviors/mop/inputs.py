"""Performers' inputs for action following: puck path features, touches and mocap streams.

A :class:`Performer` concatenates its inputs into one feature vector per sample (MOP's multiple
input sources) and says when it rests (its gesture has ended), so its follower can wait for the
next gesture.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from behaviors.motion.clips import ClipError

#: Units of the puck path features (dx, dy, heading, speed): columns of one unit get the same
#: tolerance (a puck's x and y), and a turn of 1 rad weighs like 10 cm.
PUCK_UNITS = np.array([0.1, 0.1, 1.0, 0.1])
#: Tracking jitter of the puck path features (dx, dy, heading, speed; metres, radians, m/s): a
#: take's differences within it are stillness (:func:`behaviors.mop.take.moving_part`).
#: 0.3 mm of position jitter reads as speeds up to 0.03 m/s at 30 Hz and 0.06 m/s at 60 Hz
#: (99th percentile), 0.8 mm as 0.09 and 0.15 m/s.
PUCK_JITTER = np.array([0.001, 0.001, 0.02, 0.1])


class PuckInput:
    """A puck's path features (:class:`PathFeatures`: dx, dy relative to where the gesture
    started, heading turned since, speed), a chosen subset of them. NaN while the puck is absent."""

    def __init__(self, puck_id: int, features: Sequence[str] = ("dx", "dy"),
                 rest_time: float = 0.8, prefix: str = "", rest_radius: float = 0.003) -> None:
        from behaviors.mop.features import PATH_FEATURE_NAMES, PathFeatures
        unknown = [f for f in features if f not in PATH_FEATURE_NAMES]
        if unknown or not features:
            raise ClipError(f"puck features {list(features)}: "
                            f"choose from {', '.join(PATH_FEATURE_NAMES)}")
        self.puck_id = int(puck_id)
        self._cols = [PATH_FEATURE_NAMES.index(f) for f in features]
        self.names = tuple(prefix + f for f in features)
        self.units = PUCK_UNITS[self._cols]
        #: the follower's floor of every template's scale (:attr:`PathFeatures.min_scale`)
        self.min_scale = PathFeatures.min_scale[self._cols]
        self.jitter = PUCK_JITTER[self._cols]
        self._pf = PathFeatures(rest_radius=rest_radius, rest_time=rest_time)

    @property
    def shown(self) -> str:
        """How the studio names it: "puck 1"."""
        return f"puck {self.puck_id}"

    def absent(self, frame: object) -> bool:
        """Is the puck missing from ``frame`` (its read NaN, no sample)?"""
        return frame.puck(self.puck_id) is None  # type: ignore[attr-defined]

    def read(self, frame: object, t: float) -> np.ndarray:
        p = frame.puck(self.puck_id)  # type: ignore[attr-defined]
        if p is None:
            return np.full(len(self._cols), np.nan)
        return self._pf.step(p.x, p.y, p.angle, t)[self._cols]

    @property
    def resting(self) -> bool:
        """The puck has been still for ``rest_time``: its gesture has ended."""
        return self._pf.resting

    @property
    def origin(self) -> np.ndarray:
        """Where the gesture started, in the features' terms: each feature is the pose's
        (x, y in metres, heading turned in radians) less this; speed has none (0)."""
        pf = self._pf
        return np.array([pf.origin[0], pf.origin[1], pf._origin_turn, 0.0])[self._cols]

    @property
    def still(self) -> int:
        """Samples read since the puck last moved (:attr:`PathFeatures.still`)."""
        return self._pf.still

    def state(self) -> Any:
        """Its path's state (:meth:`PathFeatures.state`), JSON-able."""
        return self._pf.state()

    def set_state(self, state: Any) -> None:
        self._pf.set_state(state)

    def restart(self, frame: object, t: float) -> None:
        """Start a gesture here (a designer's recording begins)."""
        p = frame.puck(self.puck_id)  # type: ignore[attr-defined]
        if p is not None:
            self._pf.reset(p.x, p.y, p.angle, t)


class TouchInput:
    """The first finger on the table (lowest id): dx, dy (metres) from where its gesture
    started, NaN while no finger touches. A gesture starts where the finger touches down and,
    as a puck's (:class:`PathFeatures`), where it settled once it has stood still for
    ``rest_time``: a still finger rests as a still puck does. Measured on the example
    installation (``tests/mop/test_resume.py``): resting only when lifted, a finger held still
    1-3 s part way through an action drove it through the whole pause, and a different gesture
    drawn on after it was never recognised (a wrong action drove 16-22% of it); with the rest
    nothing drives it after the rest time, the next gesture is driven 68-76% of it (as after a
    lift) with no wrong action, and the paused action is resumed over 0.81-0.98 of its second
    half (0.85-0.99 unrested)."""

    def __init__(self, prefix: str = "", rest_time: float = 0.8,
                 rest_radius: float = 0.003) -> None:
        from behaviors.mop.features import PathFeatures
        self.names = (prefix + "dx", prefix + "dy")
        self.units = np.array([0.1, 0.1])
        self.min_scale = np.array([0.01, 0.01])   # metres, as a puck's path
        self.jitter = PUCK_JITTER[:2]
        self._id: int | None = None
        self._pf = PathFeatures(rest_radius=rest_radius, rest_time=rest_time)
        self._started = False

    shown = "finger"   # how the studio names it

    def absent(self, frame: object) -> bool:
        """Does no finger touch in ``frame`` (its read NaN, no sample)?"""
        return not getattr(frame, "touches", ())

    def read(self, frame: object, t: float) -> np.ndarray:
        touches = getattr(frame, "touches", ())
        if not touches:
            self._id = None
            return np.full(2, np.nan)
        touch = next((c for c in touches if c.id == self._id), None)
        if touch is None:
            touch = min(touches, key=lambda c: c.id)
            self._id, self._started = touch.id, True
            self._pf.reset(touch.x, touch.y, 0.0, t)
        return self._pf.step(touch.x, touch.y, 0.0, t)[:2]

    @property
    def resting(self) -> bool:
        """No finger on the table, or the finger has stood still for ``rest_time``: the next
        move starts a new gesture."""
        return self._id is None or self._pf.resting

    @property
    def origin(self) -> np.ndarray:
        """Where the gesture started (x, y metres; NaN after :meth:`restart` until a finger
        touches): dx, dy are the finger's position less this. A finger lifted part way through
        an action and put down again reads from 0, 0; the action resumed reads it against the
        first finger's origin (:mod:`behaviors.mop.resume`)."""
        return np.array(self._pf.origin[:2]) if self._started else np.full(2, np.nan)

    @property
    def still(self) -> int:
        """Samples read since the finger last moved (:attr:`PathFeatures.still`; 1 while none
        touches)."""
        return self._pf.still if self._id is not None else 1

    def state(self) -> Any:
        """The finger followed, whether a gesture started and its path's state, JSON-able."""
        return {"finger": self._id, "started": self._started, "path": self._pf.state()}

    def set_state(self, state: Any) -> None:
        finger = state["finger"]
        if finger is not None and not isinstance(finger, int):
            raise ValueError(f"finger {finger!r}: expected a touch id or null")
        self._pf.set_state(state["path"])
        self._id, self._started = finger, bool(state["started"])

    def restart(self, frame: object, t: float) -> None:
        """Start a gesture at the next touch (a finger down now is read as touching down)."""
        self._id, self._started = None, False


class StreamInput:
    """Chosen columns of a named motion-capture stream. NaN while the stream is absent or too
    short.

    ``relative_to``: columns of the same stream (a root's or a head's x, y[, z]) subtracted from
    every group of as many chosen columns, sample by sample, so a body's joints read in the
    root's frame and a face's points in the head's (MOP's paper, 3.1.1: the user's root position
    is not included; face features are local to the head). Without it a stream in world
    coordinates carries the performer's walking into every feature: performed while walking
    0.5 m sideways, a circle and a wave drove their character 0% of their second half, and 100%
    read relative to the root, as in place (``tests/mop/test_stream_relative.py``)."""

    def __init__(self, stream: str, columns: Sequence[int], prefix: str = "",
                 relative_to: Sequence[int] | None = None) -> None:
        self.stream = stream
        self.columns = np.asarray(columns, dtype=int)
        self.relative_to = None if not relative_to else np.asarray(relative_to, dtype=int)
        if self.relative_to is not None and len(self.columns) % len(self.relative_to):
            raise ClipError(f"stream {stream!r}: {len(self.columns)} column(s) do not split into "
                            f"groups of {len(self.relative_to)} (relative_to's columns)")
        #: ``<stream>_<column>``; read relative, ``<stream>_<column>-<its root column>``:
        #: a template recorded without relative_to (world coordinates) is refused by its
        #: column names rather than loaded and never matched
        self.names = tuple(f"{prefix}{stream}_{c}" for c in columns) if self.relative_to is None \
            else tuple(f"{prefix}{stream}_{c}-{self.relative_to[k % len(self.relative_to)]}"
                       for k, c in enumerate(columns))
        #: A stream's columns have no known units: the follower takes them from the templates.
        self.units = None
        self.min_scale = None
        self.jitter = None
        #: Why the stream cannot be read (it has too few columns), or None.
        self.problem: str | None = None
        #: every column read: the chosen ones, then relative_to's others
        self._read = [int(c) for c in self.columns] + [
            int(c) for c in (() if self.relative_to is None else self.relative_to)
            if c not in self.columns]
        self._last = max(self._read)   # the highest column read

    @property
    def shown(self) -> str:
        """How the studio names it: "stream arm"."""
        return f"stream {self.stream}"

    def _lookup(self, frame: object) -> tuple[Any, bool]:
        """The stream's array in ``frame`` (None when missing), and whether it is too short
        to read every column :attr:`_read`."""
        a = getattr(frame, "streams", {}).get(self.stream)
        return a, a is not None and a.size <= self._last

    def absent(self, frame: object) -> bool:
        """Is the stream missing from ``frame``, or too short (its read NaN, no sample)?"""
        a, short = self._lookup(frame)
        return a is None or short

    def read(self, frame: object, t: float) -> np.ndarray:
        a, short = self._lookup(frame)
        self.problem = (f"stream {self.stream!r} has {a.size} column(s), reads column(s) "
                        f"{', '.join(str(c) for c in self._read)}") if short else None
        if a is None or short:
            return np.full(len(self.columns), np.nan)
        a = np.asarray(a, dtype=float)
        x = a[self.columns]
        if self.relative_to is not None:
            x = (x.reshape(-1, len(self.relative_to)) - a[self.relative_to]).ravel()
        return x

    #: A stream has no notion of rest: its performer is always performing.
    resting = False

    def state(self) -> Any:
        """None: a stream's read depends on its frame alone."""
        return None

    def set_state(self, state: Any) -> None:
        pass

    def restart(self, frame: object, t: float) -> None:
        pass


class Performer:
    """A named performer: several inputs concatenated into one feature vector (MOP's multiple
    input sources)."""

    def __init__(self, name: str, inputs: Sequence[PuckInput | TouchInput | StreamInput]) -> None:
        self.name = name
        self.inputs = tuple(inputs)
        self.names = tuple(n for i in self.inputs for n in i.names)

    @property
    def dim(self) -> int:
        return len(self.names)

    @property
    def units(self) -> np.ndarray | None:
        """The features' units (d,), or None when an input's are unknown (a stream)."""
        parts = [i.units for i in self.inputs]
        return None if any(u is None for u in parts) else np.concatenate(parts)

    @property
    def min_scale(self) -> np.ndarray | None:
        """The smallest spread (d,) worth telling apart in each feature (none for a stream's
        columns), the follower's floor of every template's scale; None when no input has one.
        Unfloored, one action whose path moved a few millimetres (a designer's nudge) shrank
        the follower's still radius to its spread, and no other action drove again (a circle
        beside a 1 mm action: valid 0% of its second half, 94% with the floor)."""
        return self._joined("min_scale")

    @property
    def jitter(self) -> np.ndarray | None:
        """Each feature's tracking jitter (d,; 0 for a stream's columns), None when no input
        knows its own."""
        return self._joined("jitter")

    def _joined(self, name: str) -> np.ndarray | None:
        """The inputs' per-feature figure ``name`` side by side (d,; 0 where an input has
        none), None when no input has one."""
        parts = [getattr(i, name) for i in self.inputs]
        if all(m is None for m in parts):
            return None
        return np.concatenate([np.zeros(len(i.names)) if m is None else m
                               for i, m in zip(self.inputs, parts)])

    def read(self, frame: object, t: float) -> np.ndarray:
        return np.concatenate([i.read(frame, t) for i in self.inputs])

    @property
    def problem(self) -> str | None:
        """Why an input cannot be read at the last :meth:`read` (a stream with too few
        columns: nothing could be followed, and nothing said so), or None."""
        return next((p for p in (getattr(i, "problem", None) for i in self.inputs) if p), None)

    @property
    def resting(self) -> bool:
        """Every input rests (after :meth:`read`): the performer's gesture has ended, so its
        followers wait for the next one and drive nothing meanwhile."""
        return all(i.resting for i in self.inputs)

    @property
    def origin(self) -> np.ndarray:
        """Where the gesture started (d,), in the features' terms (:attr:`PuckInput.origin`,
        :attr:`TouchInput.origin`; 0 for a stream's columns): a feature read against another
        origin is shifted by the difference."""
        return np.concatenate([i.origin if hasattr(i, "origin") else np.zeros(len(i.names))
                               for i in self.inputs])

    @property
    def still(self) -> int:
        """Samples read since a puck of this performer last moved (1: one just moved; 1
        without pucks)."""
        return min((i.still for i in self.inputs if hasattr(i, "still")), default=1)

    def restart(self, frame: object, t: float) -> None:
        for i in self.inputs:
            i.restart(frame, t)

    def state(self) -> list[Any]:
        """Each input's state (where its gesture started, whether it rests), JSON-able: what a
        recording part carries so that, replayed alone, the performer starts as it was."""
        return [i.state() for i in self.inputs]

    def set_state(self, state: Any) -> None:
        """Go on from :meth:`state`; ValueError (or KeyError, TypeError) for one that is not
        this performer's."""
        if not isinstance(state, list) or len(state) != len(self.inputs):
            raise ValueError(f"performer {self.name!r}: expected the states of its "
                             f"{len(self.inputs)} input(s)")
        for i, s in zip(self.inputs, state):
            i.set_state(s)
