"""The studio's session log: one JSON line per try, and a review sheet (PNG) per try.

``<folder>/session-YYYYmmdd-HHMMSS.jsonl``: each line ``{"target", "what", "time" (UTC ISO),
"duration_s", "samples", "training_s", "outcome" (kept | discarded | redone | too short |
refused | quit: tried, not kept, when the studio closed), "name" (kept name), "review" (PNG file
name, or ""), "take" (a quit's only: the file beside the log its take was saved in,
:meth:`SessionLog.save_take`), "take_state" (with "take": the studio's state it was saved in,
trying | training | recording | ready), "take_reaction" (with "take": a sequential take's
reaction cut short, its file)}``; a library item renamed (F2, or its undo) is a line of its own,
outcome "renamed", ``name`` the new name and ``renamed_from`` the old (the reader gives a take
kept earlier the name its folder has); so are a keep undone (U after K, outcome "keep undone"),
an item deleted (Delete, "deleted") and its undo ("restored"), ``name`` the item's name (the
reader gives the take kept under that name the outcome: a take undone or deleted is not counted
kept, one restored is again). Each line is written, flushed and fsynced on its own, so a power cut
loses at most the line being written. Review sheets are drawn in a background
thread (one at a time; a try arriving while one is drawn gets none): one thread for the whole
process, because matplotlib keeps each font open once per thread that draws (up to 64): a
thread per sheet or per studio build would leave two more files open and their fonts in memory
at each applied config edit of a kiosk (measured: 13 -> 28 files in 20 edits). Closing a
studio build waits for its own sheet; the thread ends where the run ends.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import logging
import os
import queue
import threading
from pathlib import Path
from typing import Callable

import numpy as np

from behaviors.worker import FINISH_S, ending, job_thread, next_job
from tabletop.studio.take import ITEM_LINES, Target, Try

log = logging.getLogger("tabletop")


def _load_plotting() -> None:
    if ending():    # a quit before it ran: nothing is drawn any more
        return
    from tabletop.studio.review import warm_plotting
    try:
        warm_plotting()
    except Exception:  # drawn sheets will say why; the studio runs without them
        log.exception("the plotting library for review sheets did not load")


_Jobs = queue.SimpleQueue   # of (job, its done event), or None: the drawer's end
_drawer_lock = threading.Lock()
_drawer: tuple[threading.Thread, _Jobs] | None = None   # the drawing thread and its own queue
_warmed = False


def _draw_jobs(jobs: _Jobs) -> None:
    """The drawing thread: each job of its own queue in turn; a job that fails is logged and
    the next runs. It ends at :func:`end_drawing`'s None, or once the main thread has ended
    (behaviors.worker.next_job: not a daemon, as matplotlib's native code must not be left
    running while the interpreter finalises). Its queue is its own, so a drawer still finishing
    a slow sheet after :func:`end_drawing` gave up waiting takes its own end and no later
    drawer's jobs: one drawer serves at a time."""
    while True:
        item = next_job(jobs)
        if item is None:
            return
        job, done = item
        try:
            job()
        except Exception:   # the studio runs on without that sheet
            log.exception("a review sheet was not drawn")
        finally:
            done.set()
            job = done = None   # nothing of the last sheet kept alive while the thread waits


def draw_later(job: Callable[[], None]) -> threading.Event:
    """Run ``job`` in the process's one drawing thread (started on first use); the event is
    set once it ran."""
    global _drawer
    done = threading.Event()
    with _drawer_lock:
        if _drawer is None or not _drawer[0].is_alive():
            jobs: _Jobs = queue.SimpleQueue()
            _drawer = job_thread(_draw_jobs, (jobs,), name="review"), jobs
        _drawer[1].put((job, done))
    return done


def end_drawing(timeout: float = FINISH_S) -> bool:
    """End the drawing thread once the sheets queued for it are drawn (a later sheet starts
    another); waits up to ``timeout`` seconds and says whether it ended. Called once, where
    the run ends (:meth:`tabletop.kiosk.runner.Runner.run`), not at each studio build's close:
    each new drawer would open matplotlib's fonts again."""
    global _drawer
    with _drawer_lock:
        drawer, _drawer = _drawer, None
    if drawer is None or not drawer[0].is_alive():
        return True
    drawer[1].put(None)   # the thread's end (next_job's None)
    drawer[0].join(timeout)
    return not drawer[0].is_alive()


def _warm_once() -> threading.Event:
    """The plotting library loaded in the drawing thread, once for the process."""
    global _warmed
    if _warmed:
        done = threading.Event()
        done.set()
        return done
    _warmed = True
    return draw_later(_load_plotting)


def unusable(folder: Path) -> str:
    """Why ``folder`` cannot hold the session log ("" when it can, or can be made): its
    nearest existing ancestor must be a folder this process may write in. Nothing is made."""
    p = Path(folder).absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    if not p.is_dir():
        return f"{p} is not a folder"
    if not os.access(p, os.W_OK | os.X_OK):
        return f"{p} is not writable"
    return ""


def left_at_quit(folder: Path) -> tuple[Path, str, Path | None] | None:
    """The take the latest session log in ``folder`` names as saved at quit (its last line's
    ``take``), while that file is there: (its file, the studio's state it was saved in
    (``take_state``: "" in a log older than that key), a sequential take's reaction cut short
    (``take_reaction``'s file, while there, else None)); None otherwise (or unreadable)."""
    try:
        logs = sorted(Path(folder).glob("session-*.jsonl"))
        lines = logs[-1].read_text(encoding="utf-8").split("\n") if logs else []
        last = json.loads(next(x for x in reversed(lines) if x.strip())) if lines else None
    except (OSError, ValueError, StopIteration, UnicodeDecodeError):
        return None
    if not isinstance(last, dict) or last.get("outcome") != "quit" or \
            not isinstance(last.get("take"), str) or not last["take"]:
        return None
    take = logs[-1].parent / Path(last["take"]).name
    if not take.is_file():
        return None
    state, react = last.get("take_state"), last.get("take_reaction")
    react = logs[-1].parent / Path(react).name if isinstance(react, str) and react else None
    return (take, state if isinstance(state, str) else "",
            react if react is not None and react.is_file() else None)


class SessionLog:
    """A studio session's log, ``session-STAMP.jsonl`` in ``folder``: one line per try and per
    library change, each try's review sheet (PNG) drawn beside it off the loop when
    ``review``."""

    def __init__(self, folder: Path, review: bool = True) -> None:
        self.folder = Path(folder)
        self.failing = ""           # why the last line could not be written ("" when it was)
        stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
        self.path = self.folder / f"session-{stamp}.jsonl"
        self.review = review
        self._drawn: threading.Event | None = None   # set once the sheet being drawn is done
        self.lines = 0
        if review:   # the plotting library loads at start, off the loop, not in the first try
            self._drawn = _warm_once()

    def log_try(self, t: Try, target: Target) -> None:
        """Append try ``t`` of ``target``, its review sheet started when it has a demonstration
        and no sheet is being drawn."""
        if t.outcome in ITEM_LINES:     # a line of its own: no samples, no sheet
            self._append(t)
            return
        demo = getattr(target, "demo", None)
        if demo is not None:
            t.samples = int(len(demo))
        if self.review and demo is not None and len(demo) >= 2 and not (
                self._drawn is not None and not self._drawn.is_set()):
            png = self.path.with_suffix("").name + f"-try{len(self._names()) + 1:03d}.png"
            t.review = png
            what, demo, path = target.what, np.array(demo), self.folder / png
            take_params = getattr(target, "take_params", None)   # what the take trained with
            params = take_params() if callable(take_params) else None
            self._drawn = draw_later(lambda: self._draw(what, demo, t, path, params))
        self._append(t)

    def save_take(self, suffix: str, text: str) -> str:
        """A take tried and not kept, or still recorded, at quit, written atomically beside
        the log as ``session-STAMP-takeNNN`` + ``suffix`` (NNN: the log line that names it):
        its path, or "" when it could not be written (said in the log). Not in any library:
        nothing loads it; a designer gets it back from there."""
        from tabletop.files import atomic_write_text
        path = self.folder / (self.path.with_suffix("").name + f"-take{self.lines + 1:03d}"
                              + suffix)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            atomic_write_text(path, text)
        except OSError as exc:
            log.warning("studio: the take was not saved: %s", self._why(exc, path))
            return ""
        return str(path)

    def _why(self, exc: OSError, path: Path) -> str:
        """Why ``path`` beside the log was not written: a file standing where the folder
        would be is named (the system said "File exists"), else the system's reason."""
        from tabletop.files import file_on_path
        blocker = file_on_path(self.folder)
        if blocker is not None:
            return f"{blocker} is a file, not a folder"
        return f"{getattr(exc, 'filename', None) or path}: {exc.strerror or exc}"

    def _names(self) -> list[str]:
        return [p.name for p in self.folder.glob(self.path.with_suffix("").name + "-try*.png")] \
            if self.folder.is_dir() else []

    def _append(self, t: Try) -> None:
        d = dataclasses.asdict(t)
        for key in ("renamed_from", "take", "take_state", "take_reaction"):
            if not d[key]:      # only a rename's, a quit's line has it
                del d[key]
        d["time"] = _dt.datetime.fromtimestamp(d.pop("started"), _dt.timezone.utc).isoformat(
            timespec="seconds")
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            with open(self.path, "a", encoding="utf-8") as f:
                f.write(json.dumps(d) + "\n")
                f.flush()
                os.fsync(f.fileno())
        except OSError as exc:   # (a disk full or gone): one line while it lasts, no traceback
            why = self._why(exc, self.path)
            if why != self.failing:
                log.warning("studio: session log not written: %s", why)
            self.failing = why
            return
        self.failing = ""
        self.lines += 1

    def _draw(self, what: str, demo: np.ndarray, t: Try, path: Path,
              params: dict | None = None) -> None:
        from tabletop.studio.review import review_sheet
        try:
            review_sheet(what, demo, path, title=f"{t.target}: {t.outcome} {t.name}".strip(),
                         params=params)
        except OSError as exc:     # where the log is said too: one line, no traceback
            log.warning("review sheet %s not drawn: %s", path.name, self._why(exc, path))
        except Exception:  # a review sheet is a convenience: never stop the studio
            log.exception("review sheet %s not drawn", path)

    def close(self, timeout: float = FINISH_S) -> None:
        """The studio closes: waits up to ``timeout`` seconds for its sheet being drawn. The
        drawing thread serves the next studio build (a kiosk's applied config edit) and ends
        with the run (:func:`end_drawing`)."""
        self.wait(timeout)

    def wait(self, timeout: float = 30.0) -> None:
        """Wait up to ``timeout`` seconds for the review sheet being drawn (tests, shutdown)."""
        if self._drawn is not None:
            self._drawn.wait(timeout)
