"""Behaviour folders loaded and trained in a worker thread, swapped in between ticks.

Training a stored behaviour inside a tick stalled that tick 44-67 ms for an 80 s demonstration
(about 400 ms for 600 s). :class:`BehaviorReloader` (a Puppet Master engine outside the studio)
and the studio's library picks (:class:`~tabletop.studio.targets.PuppetMasterTarget`) hand the
folder to a :class:`~behaviors.worker.Worker`; the character plays on with the behaviour it has
and the new one (with its reactor, built in the worker) is played from a tick boundary.

A hot reload happens on the wall clock (the folder's files change), so a recording carries it:
the frame whose engines first play the new behaviour holds, in ``consumed["reload"]["behaviors"]``,
what it was trained from (name, parameters, the demonstration's float64 bytes in base64, encoded
in the worker), and a replay trains it within that frame (:class:`RecordedReloads`), bit for bit.
A reload that fails is recorded too, as the label's note (``consumed["reload"]["notes"]``), so
the replayed labels say "bad file" from the same frame as live. The studio's MOP and
touch-pose library files changed on disk are recorded the same way, as the files read
(:class:`LibraryReloads`, replayed by :class:`RecordedLibraries`).
"""

from __future__ import annotations

import base64
import dataclasses
import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable

import numpy as np

from behaviors.worker import Worker, close_workers
from tabletop import library
from tabletop.frames import Frame, InputError
from tabletop.kiosk.watch import Poller, tree_signature

if TYPE_CHECKING:
    from tabletop.frames import Engine
    from tabletop.plugins.puppet_master import PuppetMasterEngine

log = logging.getLogger("tabletop")


def stored_params(stored: library.StoredBehavior, rate_hz: float | None) -> dict[str, Any]:
    """The parameters a stored behaviour trains with: its own, at the engine's rate (Hz) where
    its config gives one."""
    params = dict(stored.parameters)
    if rate_hz is not None:
        params["rate_hz"] = rate_hz
    return params


def load_and_train(folder: Path, rate_hz: float | None,
                   table: tuple[float, float, float, float]) -> tuple[Any, Any, dict[str, Any]]:
    """Read ``folder`` and train it: (behaviour, reactor on ``table``, metres, what it was
    trained from as a recording keeps it). A bad or half-written folder raises InputError
    naming the file."""
    from behaviors.puppet_master.engine import Behavior, Reactor
    stored = library.load_behavior(folder)
    params = stored_params(stored, rate_hz)
    try:
        behavior = Behavior.train(stored.demonstration, **params)
    except InputError as exc:   # a parameter of behavior.yaml: named at its key
        said = library.parameter_refused(stored, exc, () if rate_hz is None else ("rate_hz",))
        if said is None:
            raise
        raise InputError(said) from None
    return behavior, Reactor(behavior, table), library.recorded_source(stored.name, params,
                                                                       stored.demonstration)


def trained_from(source: dict[str, Any]) -> Any:
    """The behaviour a recorded reload's ``source`` (:func:`load_and_train`) trains to;
    InputError naming what is wrong when the record cannot be read. Only the decoding is
    called unreadable: training's own refusal (a demonstration too short) is raised as
    training gives it."""
    from behaviors.puppet_master.engine import Behavior
    try:
        demo = np.frombuffer(base64.b64decode(source["demonstration"], validate=True),
                             dtype="<f8").reshape(source["shape"]).astype(float)
        params = dict(source["parameters"])
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"its record is unreadable ({type(exc).__name__}: {exc})") from None
    return Behavior.train(demo, **params)


class BehaviorReloader:
    """Frame filter for a Puppet Master engine outside the studio: its behaviour folder is
    reloaded when its files change, read and trained in a worker (``background``; else within
    the tick) while the behaviour in play goes on; the new one plays from the first tick after
    the worker is done. A bad file is logged once and shown in the character's label, and the
    behaviour that was playing goes on.

    ``kept``: the reloads (``{"behaviors": source, "notes": note}``) of a behaviour a config
    edit's rebuild kept playing (:func:`keep_playing`), put into the first frame so that its
    replay plays it from there.

    ``target``: the studio's target driving the engine (designer mode), which reloads its
    folder (:mod:`tabletop.studio.pm_shelf`): this filter then only puts ``kept`` into the
    first frame and holds the start's :attr:`problem` (the status's ``behavior_errors``)
    while the engine plays the behaviour it started with (the one kept, or none; a take tried
    over it is not another): once the studio plays another (the folder fixed and reloaded,
    another picked, a take kept) the problem is the studio's."""

    def __init__(self, engine: PuppetMasterEngine, background: bool = True,
                 kept: dict[str, Any] | None = None, target: Any = None) -> None:
        self.engine, self.target = engine, target
        self.folder = Path(engine.folder)
        watch = target is None
        self.poller = (Poller(self.folder, read=getattr(engine, "folder_read", None))
                       if watch else None)
        self._started = engine.behavior          # (a target's: what the problem is about)
        # the file that went bad (None: the folder read well), from the engine's build on
        self.problem: str | None = getattr(engine, "problem", "") or None
        if kept is not None and self.problem:
            self.problem = f"{self.problem}{KEPT}"
        self._first = kept
        self.worker = Worker("puppet-master-reload") if background and watch else None
        self.loading = False          # a job is in the worker

    def __call__(self, frame: Frame | None = None) -> Frame | None:
        """A frame filter: ``frame``, holding what a behaviour played from it was trained from
        (``consumed["reload"]``, for replays)."""
        done = None
        if self._first is not None and frame is not None:
            first, self._first = self._first, None
            for key, value in first.items():
                frame = _recorded(frame, key, self.engine.name, value)
        if self.poller is None:
            playing = self.engine.behavior
            if getattr(self.target, "pending", None) is not None:   # a take tried over it
                playing = self.target.previous[0]
            if self.problem and playing is not self._started:
                self.problem = None
            return frame
        if self.loading and self.worker is not None:
            done = self._apply(self.worker.poll())
        if self.poller.changed():
            args = (self.folder, self.engine.rate_hz, self.engine.table)
            if self.worker is None:
                try:
                    done = self._apply(load_and_train(*args))
                except InputError as exc:
                    done = self._apply(exc)
            else:
                self.loading = True   # a job still running is dropped for the newer files
                self.worker.start(load_and_train, *args)
        if done is None or frame is None:
            return frame
        return _recorded(frame, done[0], self.engine.name, done[1])

    def wait(self) -> None:
        """Wait for the job in the worker and play its behaviour (tests; the loop never waits)."""
        if self.loading and self.worker is not None:
            self.worker.wait()
            self._apply(self.worker.poll())

    def _apply(self, done: tuple[Any, Any, dict[str, Any]] | Exception | None
               ) -> tuple[str, Any] | None:
        """Play a finished job's behaviour, or keep the one in play and say why in the label:
        what a recording keeps of it (``("behaviors", source)`` or ``("notes", note)``)."""
        if done is None:
            return None
        self.loading = False
        if isinstance(done, Exception):
            playing = self.engine.behavior is not None
            self.problem = f"{done}{KEPT}" if playing else str(done)
            self.engine.note = (f"bad file, still playing the previous behaviour: {done}"
                                if playing else f"bad file, no behaviour until it is fixed: {done}")
            log.error("behaviour not reloaded: %s", done)
            return "notes", self.engine.note
        behavior, reactor, source = done
        self.engine.play(behavior, source["name"], reactor)
        self.engine.played_from = (behavior, lambda: source)
        self.problem = self.engine.note = ""
        log.info("behaviour %s reloaded", self.folder)
        return "behaviors", source

    def close(self) -> None:
        """The loop closes its filters: the worker's thread ends once a reload queued or
        training in it has run, waited for up to :data:`~behaviors.worker.FINISH_S`; that
        reload's behaviour is not played (the installation closing is not polled again)."""
        close_workers(self.worker)


KEPT = "; refused, still playing the behaviour read before"
"""Ends a behaviour error (the status's ``behavior_errors``) whose character plays on."""


def _recorded(frame: Frame, key: str, name: str, value: Any) -> Frame:
    """``frame`` holding ``value`` as engine ``name``'s ``consumed["reload"][key]``."""
    reload = frame.consumed.get("reload", {})
    entries = {**reload.get(key, {}), name: value}
    return dataclasses.replace(frame, consumed={**frame.consumed,
                                                "reload": {**reload, key: entries}})


def keep_playing(engine: PuppetMasterEngine,
                 played: tuple[Any, Callable[[], dict[str, Any]]] | None
                 ) -> dict[str, Any] | None:
    """A config edit's rebuild whose behaviour folder now holds a bad file builds ``engine``
    without a behaviour (:func:`tabletop.plugins.puppet_master.build`); the character plays
    on with the one its previous engine ``played`` (the behaviour and what it was trained
    from) rather than leave the table: retrained only when the edit changed its ``rate_hz``.
    Returns what its reloader records in the first frame (None: nothing kept)."""
    if played is None or engine.behavior is not None or not getattr(engine, "problem", ""):
        return None
    behavior, source_of = played
    source = source_of()
    rate = engine.rate_hz
    if rate is not None and source["parameters"].get("rate_hz") != rate:
        source = {**source, "parameters": {**source["parameters"], "rate_hz": rate}}
        try:
            behavior = trained_from(source)
        except InputError as exc:
            log.error("%s: the behaviour read before cannot be trained at %g Hz: %s",
                      engine.name, rate, exc)
            return None
    engine.play(behavior, str(source["name"]))
    engine.played_from = (behavior, lambda: source)
    engine.note = f"bad file refused, still playing the behaviour read before: {engine.problem}"
    log.warning("%s plays on with the behaviour read before (the rebuild refused its new "
                "file): %s", engine.name, engine.problem)
    return {"behaviors": source, "notes": engine.note}


class RecordedReloads:
    """Replay's frame filter: a recorded frame's reloads (``consumed["reload"]``) are trained
    and played before its engines, and its failed reloads' notes put in their labels, as live.
    A reload that cannot be trained is logged and skipped (the behaviour in play goes on), and
    the frame's other engines are reloaded all the same."""

    def __init__(self, engines: Iterable[Engine]) -> None:
        self.engines = {e.name: e for e in engines}

    def __call__(self, frame: Frame) -> Frame:
        reload = frame.consumed.get("reload", {})
        for name, source in reload.get("behaviors", {}).items():
            engine = self.engines.get(name)
            if engine is None:
                continue
            try:
                engine.play(trained_from(source), str(source.get("name", "")))
            except Exception as exc:     # a bad record or a failure of training alike: this
                # engine's reload only, the frame's other engines reloaded all the same
                why = exc if isinstance(exc, InputError) else f"{type(exc).__name__}: {exc}"
                log.error("replay: recorded reload of %s for %s not trained: %s "
                          "(the behaviour in play goes on)", source.get("name"), name, why)
                continue
            engine.note = ""
        # (after the behaviours: a behaviour a rebuild kept playing comes with its note)
        for name, note in reload.get("notes", {}).items():
            if name in self.engines:
                self.engines[name].note = str(note)
        for name, entries in reload.get("actions", {}).items():   # MOP actions followed again
            if name in self.engines and isinstance(entries, list):
                from tabletop.kiosk.actions import replay_actions
                replay_actions(self.engines[name], entries)
        return frame


def library_files(path: Path) -> dict[str, str]:
    """The files below ``path`` as a studio's library watcher sees them (hidden names skipped,
    :func:`~tabletop.kiosk.watch.tree_signature`): relative name -> base64 of its bytes. A
    file gone while read is left out, as the reload that read it left it out."""
    out: dict[str, str] = {}
    for name, _mtime, _size in tree_signature(path):
        try:
            out[name] = base64.b64encode((path / name).read_bytes()).decode("ascii")
        except OSError:
            continue
    return out


LISTING = " library"
"""A record key's ending naming a Puppet Master target's library listing (:func:`watch_points`)."""

REMOVED = "-"
"""A listing record's value for a file removed from the library (not base64, so no file's)."""


def watch_points(studio: Any) -> dict[str, Poller]:
    """The pollers of the files a ``studio`` reloads, by the key its records use: each
    target's name for what :func:`watched` gives, and ``NAME library`` (:data:`LISTING`) for
    a Puppet Master target's library folder, whose listing its shelf picks from (a folder
    added or fixed there by another studio on the library is picked by ] as live)."""
    out: dict[str, Poller] = {}
    for name, t in studio.targets.items():
        if (p := watched(t)) is not None:
            out[name] = p
        if isinstance(lib := getattr(t, "lib_poller", None), Poller):
            out[name + LISTING] = lib
    return out


def watched(target: Any) -> Poller | None:
    """The poller of the files a studio ``target`` reloads when they change: a MOP
    character's library folder, a touch-pose engine's library, the folder of the Puppet
    Master behaviour in play."""
    poller = getattr(target, "_poller", None) or getattr(target, "play_poller", None)
    return poller if isinstance(poller, Poller) else None


class LibraryReloads:
    """The studio's library watching (its ``poll``, a hook after each frame's sinks) with what
    it read recorded: a MOP character's or a touch-pose engine's library files, or the folder
    of a Puppet Master behaviour in play (:func:`watched`), or a Puppet Master target's
    library listing, that changed on disk are reloaded (listed) there (:meth:`Studio.poll`),
    and the next frame, the first whose engines follow them, holds those files' bytes as
    ``consumed["reload"]["libraries"]`` ``{key: {relative name: base64}}``
    (:func:`watch_points`' keys); a replay (:class:`RecordedLibraries`) writes them
    into its own copy of the library and reloads within that frame. Files written while they
    were read are read again at the next look (the poller forgets what it saw).

    A library listing (:data:`LISTING`) records only the files changed since its last record
    (:data:`REMOVED` for one gone), leaving out the behaviour in play's folder when the same
    frame records it under the target's own name: the whole shipped library is 1.04 MB of
    JSON, and every studio keep, rename, delete or undo changes its listing."""

    def __init__(self, studio: Any) -> None:
        self.studio = studio
        self._read: dict[str, dict[str, str]] = {}
        self._sent: dict[str, dict[str, tuple[int, int]]] = {}   # listing: name -> mtime, size

    def poll(self, frame: Frame | None = None) -> None:
        """The hook: the studio's poll, and the files of each library it reloaded."""
        pollers = watch_points(self.studio)
        before = {name: p.signature for name, p in pollers.items()}
        for name in pollers:
            if name.endswith(LISTING) and name not in self._sent:
                self._sent[name] = {f: (m, n) for f, m, n in before[name] or ()}
        self.studio.poll()
        for name in sorted(pollers, key=lambda n: n.endswith(LISTING)):   # listings last
            p = pollers[name]
            if p.signature == before[name]:
                continue
            sig = tree_signature(p.path)
            if name.endswith(LISTING):
                if changes := self._changes(name, p, sig):
                    self._read[name] = {**self._read.get(name, {}), **changes}
            else:
                self._read[name] = library_files(p.path)
            if tree_signature(p.path) != sig:   # written while read: read it again
                p.signature = None

    def _changes(self, name: str, lib: Poller, sig: tuple) -> dict[str, str]:
        """The listing ``name``'s files changed since its last record (base64, or
        :data:`REMOVED`), ``sig`` its files now; the behaviour in play's folder left out when
        this frame records it under the target's name."""
        now, sent = {f: (m, n) for f, m, n in sig}, self._sent[name]
        skip = None
        play = watched(self.studio.targets.get(name[:-len(LISTING)]))
        if play is not None and name[:-len(LISTING)] in self._read:
            try:
                skip = play.path.resolve().relative_to(lib.path.resolve()).parts
            except ValueError:
                skip = None
        out: dict[str, str] = {f: REMOVED for f in sent if f not in now}
        for f, stamp in now.items():
            if sent.get(f) == stamp or skip and Path(f).parts[:len(skip)] == skip:
                continue
            try:
                out[f] = base64.b64encode((lib.path / f).read_bytes()).decode("ascii")
            except OSError:
                continue
        self._sent[name] = now
        return out

    def __call__(self, frame: Frame) -> Frame:
        """The filter: ``frame`` holding the libraries reloaded after the previous one."""
        read, self._read = self._read, {}
        for name, files in read.items():
            frame = _recorded(frame, "libraries", name, files)
        return frame


class RecordedLibraries:
    """Replay's frame filter: a recorded frame's library reloads (``consumed["reload"]
    ["libraries"]``, :class:`LibraryReloads`) written into the replay's library (files the
    record does not hold removed, hidden ones such as ``.trash`` kept; a listing's record, of
    changed files only, writes and removes just those) and reloaded by its
    studio before the frame's engines, as live. A record that names no target of this studio
    or holds a name outside its library is logged and skipped, and so is one whose library is
    not under ``base`` (the replay's folder of the recording's files): a folder too large to
    be carried is read where the installation has it, and a replay never writes there."""

    def __init__(self, studio: Any, base: Path) -> None:
        self.studio, self.base = studio, Path(base).resolve()

    def __call__(self, frame: Frame) -> Frame:
        records = frame.consumed.get("reload", {}).get("libraries", {})
        forced = False
        points = watch_points(self.studio)
        for name, files in records.items():
            poller = points.get(name)
            if poller is None:
                log.error("replay: recorded library of %r: no such studio target; skipped", name)
                continue
            if not poller.path.resolve().is_relative_to(self.base):
                log.error("replay: recorded library of %r not written: %s is not among the "
                          "recording's files (too large to be carried)", name, poller.path)
                continue
            try:
                _write_tree(poller.path, files, prune=not name.endswith(LISTING))
            except (InputError, OSError, TypeError, ValueError) as exc:
                log.error("replay: recorded library of %r not written: %s", name, exc)
                continue
            poller.signature, poller._next, forced = None, -np.inf, True
        if forced:
            self.studio.poll()
        return frame


def _write_tree(path: Path, files: dict[str, str], prune: bool = True) -> None:
    """``path`` holding ``files`` (relative name -> base64, or :data:`REMOVED`: removed);
    ``prune``: exactly those among its unhidden files (a listing's record holds only changes)."""
    data: dict[Path, bytes] = {}
    for name, text in files.items():
        rel = Path(name)
        if rel.is_absolute() or ".." in rel.parts or not rel.parts:
            raise InputError(f"{name!r} is outside the library")
        if text == REMOVED:
            (path / rel).unlink(missing_ok=True)
            continue
        data[rel] = base64.b64decode(text, validate=True)
    for name, _mtime, _size in tree_signature(path) if prune else ():
        if Path(name) not in data:
            (path / name).unlink()
    for rel, content in data.items():      # (one as it is is left: its poller sees no change)
        try:
            if (path / rel).read_bytes() == content:
                continue
        except OSError:
            pass
        (path / rel).parent.mkdir(parents=True, exist_ok=True)
        (path / rel).write_bytes(content)
