"""Engines seen by the studio: one :class:`~tabletop.studio.take.Target` adapter per engine.

:class:`PuppetMasterTarget` (a behaviour): the take is both designer pucks' poses, or with
``designer.sequential`` two parts (the main puck alone, then the reactor puck against the main
take's playback, paired by :func:`behaviors.puppet_master.sequential.pair_takes`); training is
``Behavior.train``, in a worker thread with ``designer.background_training`` (the new behaviour
and its reactor are swapped in between ticks; a library pick or reload too, in its loader:
:mod:`tabletop.studio.reloader`); kept takes are behaviour folders (:mod:`tabletop.library`).
:class:`~tabletop.studio.mop_target.MopTarget` (an action slot of one MOP character) lives in
its own module.
Library folders are renamed in place and deleted into ``<library>/.trash`` so undo restores them
(:mod:`tabletop.studio.folders`).
"""

from __future__ import annotations

import copy
import logging
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from behaviors.puppet_master.sequential import SequentialSession
from tabletop import library
from behaviors.worker import Worker, close_workers
from tabletop.frames import CharacterState, Frame, InputError
from tabletop.kiosk.watch import Poller
from tabletop.studio.folders import named_folder
from tabletop.studio.pm_shelf import BehaviorShelf
from tabletop.studio.pm_take import Unseen, motionless

if TYPE_CHECKING:
    from behaviors.puppet_master.engine import Behavior, Reactor
    from tabletop.plugins.puppet_master import PuppetMasterEngine

log = logging.getLogger("tabletop")



def default_params() -> dict[str, float | int]:
    """Every Puppet Master behaviour parameter at its default, by name."""
    from dataclasses import asdict

    from behaviors.puppet_master.params import Params
    return asdict(Params())


class PuppetMasterTarget(BehaviorShelf):
    """A Puppet Master engine in designer mode as a studio target."""

    REACTION = "the reaction against the main's playback"

    what = "behaviour"

    def __init__(self, engine: PuppetMasterEngine) -> None:
        self.engine = engine
        self.name = engine.name
        d = engine.designer
        self.main_puck, self.react_puck = d["main_puck"], d["react_puck"]
        self.lib: Path = Path(d["library"])
        self.base: Path | None = None        # the config's folder (the keep's line)
        self.config_named: dict[Path, str] = {}   # folders the config names: kept in place
        self.min_seconds = d["min_seconds"]
        self.record_marker = d.get("record_marker")
        self.take: list[tuple[float, ...]] = []
        self.sequential = bool(d.get("sequential", False))
        self.session = SequentialSession()
        self.unseen = Unseen()      # how long a needed puck was missing from the take
        self._unseen_main = Unseen()    # as it was when the reaction part began
        self.ghost: tuple[float, float, float] | None = None   # the main's playback pose
        self.react_at: tuple[float, float, float] | None = None   # the reactor puck's last
                                                                   # pose in this take
        # imported here: a studio without Puppet Master engines never loads their kernels
        from behaviors.puppet_master.training import BackgroundTrainer
        background = d.get("background_training", True)
        self.trainer = BackgroundTrainer() if background else None
        # a library behaviour picked or reloaded: trained in its own worker, played from the
        # first tick LOAD_S (frame time) after the pick (waiting there if not done yet), so
        # the tick it plays from depends on the frames alone
        self.loader = Worker("puppet-master-load") if background else None
        self._loading: Path | None = None                     # its folder, in the worker
        self._load_at = 0.0
        self._before: tuple = (None, None, None)   # (playing, play_poller, removed) before it
        self._now = 0.0                                       # this tick's frame time (s)
        self._training: np.ndarray | None = None              # the demonstration in the worker
        self._t = 0.0                                         # the last recorded frame's time
        self.demo: np.ndarray | None = None
        self.pending = None
        self.previous: tuple = (None, "")
        self.lib_poller = Poller(self.lib)
        folder = getattr(engine, "folder", None)
        self.play_poller = (Poller(Path(folder), read=getattr(engine, "folder_read", None))
                            if folder else None)
        self.playing: Path | None = Path(folder) if folder else None
        self.removed: Path | None = None     # the one in play, deleted elsewhere: it plays on
        self.news: list[str] = []            # said once by the studio
        self._yaml_before: dict[str, tuple[str, str]] = {}   # renamed: behavior.yaml's text
                                                            # before and after, for undo
        self._problems: list[str] = self._library_problems([])   # read at start, reported

    def close(self, deadline: float | None = None) -> bool:
        """The studio closes: the training and loading workers' threads end, waited for until
        ``deadline`` (:func:`~behaviors.worker.close_workers`); says whether they did."""
        return close_workers(self.trainer, self.loader, deadline=deadline)

    @property
    def cue(self) -> str:
        """The countdown's line: which puck to get ready with for the part about to start."""
        if not self.sequential:
            return (f"get ready: puck {self.main_puck} the main, puck {self.react_puck} the "
                    "reactor")
        if self.session.phase == "ready":
            return f"get ready: puck {self.react_puck} reacts to the main's playback"
        return f"get ready: puck {self.main_puck} the main"

    # --- the take ------------------------------------------------------------------------------

    def begin(self, frame: Frame) -> None:
        self.flush()                     # a library pick still training plays first
        self.take, self.ghost, self.demo = [], None, None   # (demo: the session log's figures)
        self.react_at = None
        self.unseen = Unseen()
        if self.sequential:
            self.session = SequentialSession()
            self.session.toggle(frame.t)             # the main puck alone
        self.engine.hold = self._hold

    def resume(self, frame: Frame) -> None:
        """The reaction part: the main take plays back from now."""
        if self.sequential and self.session.phase == "ready":
            self.unseen.pause()
            self._unseen_main = copy.deepcopy(self.unseen)
            self.session.toggle(frame.t)

    def retake(self) -> str:
        """After a refused take, the part recorded again alone, or "": a sequential take's
        reaction (too short, its puck unseen or never moved), its main take kept and its ghost
        back at the first pose. The designer redid the main part too."""
        s = self.session
        if not self.sequential or s.phase != "done" or len(s.main) < 2:
            return ""
        s.again()
        self.unseen = copy.deepcopy(self._unseen_main)
        self.ghost, self.engine.hold = tuple(s.main[0][1:]), self._hold
        return f"{self.REACTION} ({s.main[-1][0] - s.main[0][0]:.1f} s)"

    def _hold(self, frame: Frame) -> tuple[CharacterState, ...]:
        """While recording the character is drawn under the reactor puck; while the puck is
        lifted it stays, calmer, where the puck was last seen, and until the puck is first seen
        (a sequential take's main part records without it) where the character stood when the
        take began (the table's centre only for one never drawn), so neither moves it. The main
        take's playback (sequential) is drawn as a ghost ``NAME.main`` of kind "playback"."""
        e = self.engine
        r = frame.puck(self.react_puck)
        if r is not None:
            self.react_at = (r.x, r.y, r.angle)
            out = [e.character(r.x, r.y, r.angle, True, "recording")]
        elif self.react_at is not None:
            out = [e.character(*self.react_at, False, "recording")]
        elif e.last_pose is not None:
            out = [e.character(*e.last_pose, False, "recording")]
        else:
            x0, y0, x1, y1 = e.table
            out = [e.character((x0 + x1) / 2, (y0 + y1) / 2, 0.0, False, "recording")]
        if self.ghost is not None:
            out.append(CharacterState(f"{self.name}.main", *self.ghost, kind="playback",
                                      size=e.size, color=e.color, valid=True, label="playback"))
        return tuple(out)

    def record(self, frame: Frame) -> str:
        m, r = frame.puck(self.main_puck), frame.puck(self.react_puck)
        self._t = frame.t
        if self.sequential:
            self.ghost = self.session.record(frame.t, None if m is None else (m.x, m.y, m.angle),
                                             None if r is None else (r.x, r.y, r.angle))
            need = ((self.main_puck, m),) if self.session.phase == "main" else (
                (self.react_puck, r),)
        else:
            if m is not None and r is not None and (not self.take or frame.t > self.take[-1][0]):
                self.take.append((frame.t, m.x, m.y, m.angle, r.x, r.y, r.angle))
            need = ((self.main_puck, m), (self.react_puck, r))
        missing = [p for p, q in need if q is None]
        self.unseen.tally(frame.t, missing, [p for p, _ in need])
        return f"recording: no {', '.join(f'puck {p}' for p in missing)}" if missing else ""

    def ended(self) -> bool:
        """The main's playback has ended (sequential): the reaction part is complete."""
        return self.sequential and self.session.phase == "done"

    def cut(self) -> str:
        """The designer stopped: after the main part (long enough) the reaction follows, named
        with the playback's length (the reaction part ends with it, and REC counts up to it)."""
        s = self.session
        if not self.sequential or s.phase not in ("main", "react"):
            return ""
        secs = s.seconds()
        if s.phase == "main" and secs < self.min_seconds:
            return ""                                 # train() refuses it as too short
        if s.toggle(self._t) != "ready":
            return ""
        # the playback's first pose, still, until it plays: the designer puts the reactor
        # puck where the reaction begins, not only once the playback starts
        self.ghost = tuple(s.main[0][1:])
        return f"{self.REACTION} ({secs:.1f} s)"

    def seconds(self) -> float:
        if self.sequential:
            return self.session.seconds()
        return self.take[-1][0] - self.take[0][0] if self.take else 0.0

    def take_array(self) -> np.ndarray:
        """The take as a demonstration (n, 7), times from 0."""
        a = np.array(self.take, dtype=float).reshape(-1, 7)
        if a.size:
            a[:, 0] -= a[0, 0]
        return a

    def demonstration(self) -> np.ndarray:
        """The take as a demonstration (n, 7), at least ``min_seconds`` long (InputError)."""
        if not self.sequential:
            demo, what = self.take_array(), "both pucks"
        elif self.session.phase != "done":
            demo, what = np.array(self.session.main).reshape(-1, 4), "the main puck"
        elif len(self.session.react) < 2:   # its puck never seen while the main played back
            raise InputError(f"no reaction recorded: puck {self.react_puck} was not seen during "
                             "the main's playback")
        else:
            demo, what = self.session.demonstration(), "the reaction"
        secs = float(demo[-1, 0] - demo[0, 0]) if len(demo) else 0.0
        if secs < self.min_seconds:
            # cut: 1.96 s read "2.0 s, needs 2 s"; but not below the tenth a take of 2.3 s
            # (2.299999999999997 s between frame times near t = 100 s) reaches: it read "2.2 s"
            shown = math.floor(secs * 10 + 1e-6) / 10
            lost = self.unseen.words()     # a puck never seen made it short, not the designer
            raise InputError(f"take too short ({shown:.1f} s of {what}, needs "
                             f"{self.min_seconds:g} s{'; ' + lost if lost else ''})")
        if demo.shape[1] == 7:
            motionless(demo, self.main_puck, self.react_puck)
        return demo

    def train(self) -> str | None:
        """Train the take and play it; with background training start the worker and return
        None (:meth:`trained` swaps it in)."""
        from behaviors.puppet_master.engine import Behavior
        self.engine.hold, self.ghost = None, None
        demo = self.demonstration()
        params = self.take_params()
        if self.trainer is not None:     # (demo: a take dropped while it trains is logged whole)
            self._training = self.demo = demo
            self.trainer.start(demo, params, self.engine.table)
            return None
        self._play(Behavior.train(demo, **params), None, demo)
        return self._summary()

    def take_params(self) -> dict[str, float | int]:
        """The parameters a take trains with: the character's in play (a new take of the
        afraid character keeps its edge_percentile 50; it trained with the defaults but the
        rate and window), the engine's rate where its config gives one, and the table it is
        made on (metres; as keep() saves it, so the behaviour tried is the one kept)."""
        e = self.engine
        params = e.behavior.param_dict() if e.behavior is not None else default_params()
        x0, y0, x1, y1 = e.table
        params.update(table_width=x1 - x0, table_height=y1 - y0)
        if e.rate_hz:
            params["rate_hz"] = e.rate_hz
        return params

    def trained(self, wait: bool) -> str | None:
        """Between ticks: the worker's behaviour and reactor, once ready (``wait``: waits for
        them), play from now."""
        if wait and self.trainer is not None and self._training is not None:
            self.trainer.wait()
        done = self.trainer.poll() if self.trainer is not None else None
        if done is None or self._training is None:
            return None
        demo, self._training = self._training, None
        if isinstance(done, Exception):
            raise InputError(f"training failed: {done}")
        behavior, reactor, error = done
        if error is not None:
            raise error
        self._play(behavior, reactor, demo)
        return self._summary()

    def _play(self, behavior: Behavior, reactor: Reactor | None, demo: np.ndarray) -> None:
        e = self.engine
        self.pending, self.demo = behavior, demo
        self.previous = (e.behavior, e.behavior_name)
        e.play(behavior, "new take", reactor)

    def _summary(self) -> str:
        """What was trained, in the session log's and the review's figures: the take's
        recorded samples and seconds (the behaviour's own count, resampled at its rate, read
        428 where the review said 246 for one take of a 23 fps loop)."""
        n = len(self.demo) if self.demo is not None else 0
        secs = float(self.demo[-1, 0]) if n else 0.0
        return f"trained {n} samples ({secs:.1f} s){self.unseen.note()}"

    def tried_take(self) -> tuple[str, str] | None:
        """The take being tried (or trained) as its keep saves it: (".csv", its demonstration
        CSV, which ``tabletop behave --train`` takes); None without one."""
        if self.demo is None:
            return None
        return ".csv", library.demonstration_csv(self.demo)

    def recorded_take(self) -> tuple[str, str] | str:
        """The take still recorded at quit, as :meth:`tried_take` gives one: its demonstration
        CSV; a sequential take's main part alone (its reaction not done: ``behave
        --train-main``'s columns, times from 0; a reaction under way is
        :meth:`recorded_reaction`); or why none (a take too short to train)."""
        try:
            demo = self.demonstration()
        except InputError as exc:
            return str(exc)
        if demo.shape[1] == 7:
            return ".csv", library.demonstration_csv(demo)
        from tabletop.commands.behave import MAIN_COLUMNS
        from tabletop.files import format_csv
        return ".csv", format_csv(MAIN_COLUMNS, (demo - [demo[0, 0], 0, 0, 0]).tolist())

    def recorded_reaction(self) -> tuple[str, str] | None:
        """A sequential take's reaction under way at quit, beside its main part
        (:meth:`recorded_take`): ("-react.csv", the CSV ``behave --train-react`` takes, on the
        main part's times from 0, so the two pair); None without two samples of it."""
        s = self.session
        if not self.sequential or s.phase not in ("react", "done") or len(s.react) < 2 \
                or not s.main:
            return None
        from tabletop.commands.behave import OUT_COLUMNS
        from tabletop.files import format_csv
        react = np.array(s.react, dtype=float) - [s.main[0][0], 0, 0, 0]
        return "-react.csv", format_csv(OUT_COLUMNS, react.tolist())

    def revert(self) -> None:
        self.engine.hold, self.ghost, self._training = None, None, None
        if self.trainer is not None:
            self.trainer.cancel()                     # a job still running is dropped
        if self.pending is not None:
            self.engine.play(*self.previous)
        self.pending = None

    @property
    def kept_in(self) -> str:
        """What the keep's line adds: the library folder it was saved in."""
        return f" in {named_folder(self.lib, self.base)}"

    def keep(self) -> str:
        if self.pending is None or self.demo is None:
            raise InputError("nothing to keep")
        # with the table it was made on, as the shipped behaviours are: a room or an edge
        # margin set later (w_room, edge_percentile) measured against the take's own bounds
        default = default_params()
        folder = library.save_new(   # the rate, window and table, and any other not default
            self.lib, self.engine.designer["name"], self.demo,
            {k: v for k, v in self.pending.param_dict().items()
             if k in ("rate_hz", "window", "table_width", "table_height") or v != default[k]},
            description=f"demonstrated at the table for {self.name}",
            source="designer studio, recorded from the table")
        name = folder.name
        self.engine.behavior_name, self.playing, self.pending = name, folder, None
        # the kept take is in play, followed by its own poller: the behaviour it replaced,
        # deleted elsewhere and back, is not reloaded over it
        self.play_poller, self.removed = Poller(folder), None
        self.lib_poller.signature = ()      # the library changed: list it again
        return name
