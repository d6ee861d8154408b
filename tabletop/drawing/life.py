"""What makes still drawings feel alive: each character's presence over time, and pucks' paths.

All times are the frames' seconds (``Frame.t``), so a replay or a test sees the same motion.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field
from typing import Iterable, Sequence

import numpy as np

from tabletop.frames import CharacterState, Puck

FADE_IN_S = 0.45        # a new character fades and grows in over this
FADE_OUT_S = 0.6        # a character that left fades and shrinks out over this
SPEED_TAU_S = 0.12      # smoothing of the speed that drives squash and stretch
TRAIL_S = 0.7           # a puck's trail covers this much of its recent path
TRAIL_STEP_M = 0.012    # ... sampled every 1.2 cm of travel
LOST_S = 1.2            # a puck that left is shown as "lost" for this long
STRIDE_M = 0.05         # a reactor's feet step once per this much travel
HINT_TAU_S = 0.15       # a hinted pose (early feedback) fades in and out with this time constant
# ... and out with this one once its action drives the character: faded over HINT_TAU_S, the
# hinted pose, frozen where it was last suspected, stayed beside the acting figure for 0.45 s
# (27 frames at 60 Hz: a grey copy of the salamander's tail under its lit one, examples/mop.yaml
# at 800x600 and 1920x1080), 45% of the dancer's acting frames; at 0.04 s it is gone in 7
HINT_GONE_S = 0.04
JUMP_SPEED = 5.0        # m/s: a character moved faster than this between frames has jumped
GLIDE_S = 0.4           # ... and is drawn gliding from where it was to its place over this
# ... when it was seen there (drawn at least this opaque): a place drawn unseen is no place to
# glide from. examples/reactors.yaml's mutual pair waits one tick at the table's centre, drawn
# at alpha 0, then stands 59 px apart at 1280x720: both glided out of that one spot, the one
# below hidden by the one on top (30 px apart in frame 13 at 60 Hz, 40 px in frame 14)
SEEN_ALPHA = 0.05
# Reactors waiting on one spot (each engine's waiting place is the table's centre) are drawn side
# by side, this many of the largest one's body lengths apart (the bodies ~0.7 of their length
# wide: 6 px clear at 1280x720): examples/reactors.yaml with its pucks not yet down drew lover,
# stalker and bully as one blob (the bully's, on top of the two).
ROW_GAP = 0.9


def ease_out_back(u: float) -> float:
    """0 -> 1 with a small overshoot (a pop that settles), u in 0..1."""
    u = min(max(u, 0.0), 1.0)
    c = 1.4
    return 1 + (c + 1) * (u - 1) ** 3 + c * (u - 1) ** 2


def smoothstep(u: float) -> float:
    u = min(max(u, 0.0), 1.0)
    return u * u * (3 - 2 * u)


def seed_of(name: str) -> float:
    """A stable number in 0..1 per name: characters breathe and blink out of step."""
    return (zlib.crc32(name.encode()) % 10007) / 10007.0


def breath(t: float, seed: float, stillness: float) -> float:
    """Scale factor of a slow breath (about 1 +- 3.5 %), full when ``stillness`` is 1."""
    period = 2.8 + 1.4 * seed
    return 1.0 + 0.035 * stillness * math.sin(math.tau * (t / period + seed))


def eyes_open(t: float, seed: float) -> float:
    """1 with eyes open, down to 0.08 during a blink (0.14 s every 2.6-5.6 s, now and then
    twice)."""
    period = 2.6 + 3.0 * seed
    u = (t + 7.0 * seed) % period
    for start in (0.0, 0.3 if seed > 0.6 else -1.0):
        if start >= 0 and start <= u < start + 0.14:
            return 0.08 + 0.92 * abs((u - start) / 0.07 - 1.0)
    return 1.0


def stretch(speed: float) -> float:
    """Length factor along the motion for ``speed`` m/s: 1 at rest, up to 1.3 when fast (the
    width is divided by it: squash and stretch keep the area)."""
    return 1.0 + 0.3 * math.tanh(speed / 0.35)


def hint_level(c: CharacterState) -> float:
    """How strongly to show ``c``'s hinted pose: its likeliest hint's probability while the
    engine suspects an action but drives nothing yet (``valid`` False), else 0."""
    if c.valid or c.hint_points is None or not c.hints or c.points is None \
            or len(c.hint_points) != len(c.points):
        return 0.0
    p = max(h[1] for h in c.hints)
    return min(1.0, max(0.0, p)) if math.isfinite(p) else 0.0


@dataclass
class Presence:
    """One character as the view has seen it: when it came, how fast it moves, when it left."""

    state: CharacterState
    born: float
    t: float
    speed: float = 0.0
    vx: float = 0.0
    vy: float = 0.0
    gone: float | None = None
    seed: float = 0.0
    phase: float = 0.0          # stepping cycle, radians: advances with the distance travelled
    hint: float = 0.0           # strength 0..1 of the hinted pose shown faintly (early feedback)
    hint_points: object = None  # the last hinted pose (N x 2, table metres), kept while it fades
    hint_action: str = ""       # ... and its action's name (its label)
    glide: tuple[float, float, float] | None = None   # (t, dx, dy m): a jump being glided
    apart: tuple[float, float] = (0.0, 0.0)   # (dx, dy m): its place in a row of waiting ones

    def offset(self, t: float) -> tuple[float, float]:
        """Where it is drawn, relative to its state's place (metres): after a jump, the way back
        to where it was drawn, easing to nothing over ``GLIDE_S`` (a reactor waiting at the
        table's centre leapt 24 cm in a frame to its first place when a puck was put down),
        and its place in a row of reactors waiting on one spot (:func:`rows`)."""
        ax, ay = self.apart
        if self.glide is None:
            return ax, ay
        t0, dx, dy = self.glide
        if not 0.0 <= t - t0 < GLIDE_S:     # glided, or a frame time before the jump's
            self.glide = None
            return ax, ay
        w = 1.0 - smoothstep((t - t0) / GLIDE_S)
        return ax + dx * w, ay + dy * w

    def alpha(self, t: float) -> float:
        """Opacity 0..1 now: fading in after ``born``, fading out after ``gone``."""
        if self.gone is None and t - self.born >= FADE_IN_S:
            return 1.0                                       # (here, and in scale: settled)
        a = smoothstep((t - self.born) / FADE_IN_S)
        if self.gone is not None:
            a *= 1.0 - smoothstep((t - self.gone) / FADE_OUT_S)
        return a

    def scale(self, t: float) -> float:
        """Size factor now: grows in from 0.6 with a small overshoot, shrinks to 0.7 on leaving."""
        if self.gone is None and t - self.born >= FADE_IN_S:
            return 1.0
        s = 0.6 + 0.4 * ease_out_back((t - self.born) / FADE_IN_S)
        if self.gone is not None:
            s *= 1.0 - 0.3 * smoothstep((t - self.gone) / FADE_OUT_S)
        return s

    def stillness(self) -> float:
        """1 when still, towards 0 when moving (breathing shows when still)."""
        return math.exp(-self.speed / 0.04)


class Lives:
    """The presences of all characters, updated once per drawn frame."""

    def __init__(self) -> None:
        self.presences: dict[str, Presence] = {}

    def update(self, t: float, characters: Sequence[CharacterState]) -> list[Presence]:
        """Presences to draw at time ``t``: the current characters (in order), then the ones
        still fading out."""
        now = set()
        out = []
        for c in characters:
            now.add(c.name)
            p = self.presences.get(c.name)
            if p is None or (p.gone is not None and p.alpha(t) < 0.05):
                p = Presence(c, born=t, t=t, seed=seed_of(c.name))
                self.presences[c.name] = p
            elif p.gone is not None:  # came back while fading out: fade in from where it was
                p.born = t - FADE_IN_S * p.alpha(t)
                p.gone = None
            dt = t - p.t
            if dt > 1e-6:
                k = 1.0 - math.exp(-dt / SPEED_TAU_S)
                vx, vy = (c.x - p.state.x) / dt, (c.y - p.state.y) / dt
                if not math.hypot(vx, vy) <= JUMP_SPEED:   # a jump (or a broken pose)
                    if c.points is None and math.isfinite(vx) and math.isfinite(vy) \
                            and p.alpha(p.t) >= SEEN_ALPHA:
                        ox, oy = p.offset(t)   # glide on from where it is drawn now
                        p.glide = (t, p.state.x + ox - c.x - p.apart[0],
                                   p.state.y + oy - c.y - p.apart[1])
                    vx = vy = 0.0
                if not (math.isfinite(p.vx) and math.isfinite(p.vy)):
                    p.vx = p.vy = 0.0
                p.vx += k * (vx - p.vx)
                p.vy += k * (vy - p.vy)
                p.speed = math.hypot(p.vx, p.vy)
                p.phase = (p.phase + p.speed * dt * math.tau / STRIDE_M) % math.tau
                level = hint_level(c)
                if level or p.hint:
                    tau = HINT_GONE_S if c.valid else HINT_TAU_S
                    p.hint += (1.0 - math.exp(-dt / tau)) * (level - p.hint)
            if c.hint_points is not None and not c.valid:
                p.hint_points = c.hint_points
                p.hint_action = c.hints[0][0] if c.hints else p.hint_action
            p.state, p.t = c, t
            out.append(p)
        rows(t, out)
        if len(now) == len(self.presences):     # (none left)
            return out
        for name, p in list(self.presences.items()):
            if name in now:
                continue
            if p.gone is None:
                p.gone = t
            if t - p.gone >= FADE_OUT_S:
                del self.presences[name]
            else:
                out.append(p)
        return out


def rows(t: float, presences: Sequence[Presence]) -> None:
    """Set ``apart`` of reactors waiting (not valid) on one spot (to 1 mm): side by side across
    their heading, ROW_GAP of the largest body length apart, in the characters' order; 0 for
    every other. A presence seen (alpha >= SEEN_ALPHA) whose ``apart`` changes glides there."""
    spots: dict[tuple, list[Presence]] = {}
    for p in presences:
        c = p.state
        if c.kind == "reactor" and not c.valid and c.points is None:
            spots.setdefault((round(c.x, 3), round(c.y, 3)), []).append(p)
    for p in presences:
        c = p.state
        new = (0.0, 0.0)
        row = spots.get((round(c.x, 3), round(c.y, 3)), ()) if c.kind == "reactor" else ()
        at = [i for i, q in enumerate(row) if q is p]
        if len(row) > 1 and at:
            gap = ROW_GAP * max(q.state.size for q in row)
            k = (len(row) - 1) / 2 - at[0]
            new = (-k * gap * math.sin(c.heading), k * gap * math.cos(c.heading))
        if new != p.apart:
            ox, oy = p.offset(t)
            p.apart = new
            if p.alpha(t) >= SEEN_ALPHA:
                p.glide = (t, ox - new[0], oy - new[1])


class TrailPath:
    """A puck's recent path: at most ``limit`` points (x, y table metres, t s), oldest first, as
    rows of one array (:meth:`points`), so a frame reads every trail without a Python object per
    point (16 pucks' trails gathered from tuples cost ~0.1 ms of a busy frame)."""

    def __init__(self, limit: int = 64) -> None:
        self.limit = limit
        self.rows = np.empty((2 * limit, 3))
        self.start = self.end = 0
        self.last: tuple[float, float] | None = None    # the newest point's x, y

    def __len__(self) -> int:
        return self.end - self.start

    def append(self, x: float, y: float, t: float) -> None:
        """Add the newest point (the oldest is dropped when ``limit`` are kept)."""
        if self.end - self.start == self.limit:
            self.start += 1
        if self.end == len(self.rows):                  # move the points back to the front
            n = self.end - self.start
            self.rows[:n] = self.rows[self.start:self.end]
            self.start, self.end = 0, n
        row = self.rows[self.end]
        row[0], row[1], row[2] = x, y, t
        self.end += 1
        self.last = (x, y)

    def forget(self, t: float, span: float) -> None:
        """Drop the points more than ``span`` s older than ``t``."""
        rows = self.rows
        while self.start < self.end and t - rows[self.start, 2] > span:
            self.start += 1
        if self.start == self.end:
            self.last = None

    def points(self) -> np.ndarray:
        """The points, oldest first (a view: N x 3)."""
        return self.rows[self.start:self.end]


@dataclass
class PuckTrace:
    """One puck's recent path (table metres, seconds) and when it was last seen."""

    puck: Puck
    last_t: float
    path: TrailPath = field(default_factory=TrailPath)


class Traces:
    """Every puck's trail, and the pucks that left (shown "lost" for a moment)."""

    def __init__(self) -> None:
        self.traces: dict[int, PuckTrace] = {}

    def update(self, t: float, pucks: Iterable[Puck]) -> list[tuple[PuckTrace, str, float]]:
        """(trace, state, opacity) for every puck to draw now, the lost ones fading."""
        out = []
        here = set()
        for p in pucks:
            here.add(p.id)
            tr = self.traces.get(p.id)
            if tr is None:
                tr = self.traces[p.id] = PuckTrace(p, t)
            tr.puck, tr.last_t = p, t
            path = tr.path
            last = path.last
            if last is None or math.hypot(p.x - last[0], p.y - last[1]) >= TRAIL_STEP_M:
                path.append(p.x, p.y, t)
            path.forget(t, TRAIL_S)
            out.append((tr, p.state, 1.0))
        if len(here) == len(self.traces):       # (none lost)
            return out
        for pid, tr in list(self.traces.items()):
            if pid in here:
                continue
            age = t - tr.last_t
            if age >= LOST_S or age < 0:
                del self.traces[pid]
                continue
            tr.path.forget(t, TRAIL_S)
            out.append((tr, "lost", 1.0 - smoothstep(age / LOST_S)))
        return out
