"""The recorder sink: session recordings a kiosk can rely on (format: :mod:`tabletop.session`).

- Self-contained: the header carries the config as written and every file it refers to
  (:func:`session_header`), so a recording replays on another machine.
- Never overwrites and never collides: a folder gets ``session-DATE-TIME-MICROSECONDS.jsonl``
  and an exact ``path`` that exists already continues as ``NAME-2.jsonl``, ``NAME-3.jsonl``...;
  files are created exclusively, so two runs starting at once get two names.
- Bounded: a file reaching ``max_mb`` continues in a new file (the next part, its own header,
  times still counted from the session's start); ``keep`` removes the oldest recordings of the
  same naming in that folder down to ``keep`` files (closed sessions whole first: see
  :func:`tabletop.recordings.prune`), oldest by the ``order`` each file's header carries (one
  more than the highest in the folder when it was made), never by the clock: after the clock was set
  back (a dead RTC battery, a time server correcting it) the newest files have the oldest
  times, and pruning by modification time removed the recordings just made first.
- A write that fails (a full disk) stops recording with one clear log line; the installation
  keeps running and :attr:`Recorder.failed` says why (``tabletop run`` then exits non-zero).
  After a full disk, every ``RESUME_EVERY_S`` of frame time a new part is tried; once the disk
  takes it the recording goes on there (logged; :attr:`Recorder.gaps` keeps why it stopped).
  A disk that could not keep up (below) is tried alike, once its syncs have caught up; one
  that falls behind again waits twice as long before each try, up to an hour. A part whose
  file was removed from disk (its folder deleted) stops alike and goes on at once in a new
  part, its folder made again (looked at every ``REMOVED_CHECK_S`` of frame time): the stops and
  tries are :mod:`tabletop.recorder_resume`'s.

Durable line by line, never waiting on the frame loop: see :mod:`tabletop.recorder_sync`. A
new file is synced before its first frame (its folder entry too). More than ``max_queue`` lines
the disk has not synced yet (a disk that stopped) stop the recording like a full disk.
"""

from __future__ import annotations

import errno
import json
import logging
import os
import time
from pathlib import Path
from typing import Any, Callable

from tabletop.file_io import close_quietly
from tabletop.files import folder_failure, fsync_folder, is_stream
from tabletop.frames import Frame
from tabletop.parts import carried, header_line
from tabletop.recorder_resume import (REMOVED_CHECK_S, RESUME_EVERY_S, SLOW_RESUME_MAX_S,
                                      Resuming)
from tabletop.recorder_sync import Syncer
from tabletop.recordings import (Orders, create_part, hold, let_go, new_session, number, prune,
                                 release)
# The format lives in tabletop.session; its names are re-exported for callers of this module.
from tabletop.session import (FORMAT, VERSION, SessionError,  # noqa: F401
                              frame_to_dict, jsonable, read_frames, read_header, session_header)

log = logging.getLogger("tabletop")

MB = 2**20
DISK_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


class Recorder(Resuming, Syncer):
    """Sink writing every frame to session files (JSON Lines); see the module docstring.

    Exactly one of ``path`` (a file name) or ``folder`` is given. ``header``: from
    :func:`session_header` (built once, written at the top of every part). ``max_queue``:
    lines that may wait for the disk before the recording stops. ``clock``: monotonic seconds
    for the lines' durability (when written, when synced). ``strict`` (a start outside a
    kiosk, where someone reads the error): a folder that refuses the first file (read-only,
    no permission, a file in its place) raises SessionError; otherwise (a kiosk's start, whose
    last good config names the same folder: refusing would restart it for ever) it runs
    without recording, as after a full disk, :attr:`failed` saying why and a new part tried
    every ``RESUME_EVERY_S`` of frame time. A full disk at the start runs so even when strict
    (a table keeps running), unless ``refuse_full`` (a replay's ``--out``: no table, and the
    whole session played into no file).
    """

    name = "recorder"

    def __init__(self, path: str | Path | None = None, header: dict[str, Any] | None = None,
                 folder: str | Path | None = None, max_mb: float | None = None,
                 keep: int | None = None, config: Any = None,
                 calibration: dict[str, Any] | None = None, max_queue: int = 1024,
                 clock: Callable[[], float] = time.monotonic, strict: bool = True,
                 refuse_full: bool = False) -> None:
        if (path is None) == (folder is None):
            raise ValueError("give exactly one of path or folder")
        if header is None:
            header = session_header(config, calibration)
        self._header = dict(header)
        self.clock = clock
        if path is not None:
            p = Path(path)
            if p.is_dir():
                raise SessionError(f"{p}: is a folder; expected a file name for the recording")
            if is_stream(p):   # it recorded to /dev/null-2 or /dev/stdout-2, files in /dev
                raise SessionError(f"{p}: is a device or pipe; a recording is a file (synced, "
                                   "in parts, never overwritten): give a file name")
            self.folder, self.stem, self.suffix = p.parent, p.stem, p.suffix
        else:
            self.folder, self.stem, self.suffix = Path(folder), None, ".jsonl"
        self.max_bytes = None if max_mb is None else max(1, int(max_mb * MB))
        self.max_mb = max_mb   # as given, for the log (max_bytes / MB reads 0.299999 for 0.3)
        self.keep, self.max_queue = keep, max(1, int(max_queue))
        self.paths: list[Path] = []      # every file of this session, in order
        self._removed: Path | None = None   # its header-only part, removed at close
        self.frames = 0                  # frames written
        self._orders: Orders = {}        # recordings' header orders and sessions, read once
        self._session = new_session()    # this session's id, in every part's header
        self._order = 0                  # the last part's order, and its name's number
        self._trimmed: list[Path] = []   # its own oldest parts removed (keep): said once
        self._number = 0                 # (recordings.number)
        self.failed: str | None = None   # why recording stopped early, if it did
        self.gaps: list[str] = []        # why it stopped, for each stop it resumed after
        self._resumable = False                # stopped by a full disk: tries go on
        self._resume_at: float | None = None   # frame time of the next try, once known
        self._slow_wait_s = RESUME_EVERY_S     # before the next "cannot keep up" stop's try
        self._resumed_t: float | None = None   # frame time of the last resume
        self._last_t: float | None = None      # the last frame's time
        self._check_at: float | None = None    # frame time of the next look (REMOVED_CHECK_S)
        self._f: Any = None
        self._stopped: int | None = None   # the stopped part's mark (keep_held), till it goes on
        self._size = 0
        self._t0: float | None = None
        self._first_in_file = True
        # what the session's frames reloaded so far, and before the frame being written
        self._reloaded: dict[str, Any] = {}
        self._reloaded_before: dict[str, Any] = {}
        # the engines' states a part carries (tabletop.parts.part_states), after the last
        # frame and before the frame being written
        self.state_of: Callable[[], dict[str, Any]] | None = None
        self._state: dict[str, Any] | None = None
        self._state_before: dict[str, Any] | None = None
        self._init_syncer()
        try:
            self._open_part()
        except OSError as exc:
            if strict and (refuse_full or exc.errno not in DISK_FULL):
                if self._f is not None:   # the file the full disk took no header into
                    close_quietly(self._f)
                for p in self.paths:
                    p.unlink(missing_ok=True)
                raise SessionError(f"{self.folder}: cannot start a recording there: "
                                   f"{folder_failure(self.folder, exc)}") from None
            self._fail(exc)  # the installation runs, without recording (tries go on)
        self._start_syncer()

    @property
    def path(self) -> Path:
        """The file being written (the last one when finished; the removed one when the
        session recorded no frame)."""
        return self.paths[-1] if self.paths else self._removed

    # -- files -----------------------------------------------------------------------------------

    def _open_part(self, resumed: str | None = None) -> None:
        """A new file: the first, the next part, or one ``resumed`` after a stop for that
        reason."""
        self.folder.mkdir(parents=True, exist_ok=True)
        listed = self.keep is not None or not self.paths   # (nothing to prune: not listed)
        mine, order, candidate, f = create_part(self.folder, self.stem, self.suffix, self._orders,
                                                (self._order, self._number), listed)
        previous = self.path.name if self.paths else None
        self._f, self._size, self._first_in_file = f, 0, True
        hold(f)                          # another run's keep leaves it alone
        self.paths.append(candidate)
        self._write(header_line(self._header, order, len(self.paths), self._session,
                                self._reloaded_before, self._state_before))
        self._f.flush()
        let_go(self._stopped)            # a stopped part: the session's new one marks it now
        self._stopped = None
        # said once the disk took the header: a try on a disk still full says nothing
        if resumed is not None:
            log.info("recording resumes in %s (it stopped: %s)", candidate, resumed)
        elif previous is not None:
            log.info("recording continues in %s (%s reached %g MB)", candidate, previous,
                     self.max_mb)
        elif self.stem is not None and candidate.name != f"{self.stem}{self.suffix}":
            log.info("recording to %s (%s%s exists and is never overwritten)", candidate,
                     self.stem, self.suffix)
        if len(self.paths) == 1:         # at start-up: synced now; later parts by the syncer
            os.fdatasync(self._f.fileno())
            fsync_folder(self.folder)    # the new file's name survives a power cut too
        else:
            self._folder_dirty = True
        mine[candidate] = (order, 0.0, self._session)
        self._orders[candidate] = (order, self._session)
        self._order, self._number = order, number(candidate.name, self.stem, self.suffix)
        trimmed = prune(mine, self.keep, self.path, self.folder, self.paths)
        if trimmed and not self._trimmed:
            log.warning("recording %s: its part %s removed, as this session alone holds more "
                        "than recorder.keep (%d) parts; its oldest parts go on being removed "
                        "(each part replays on its own)", self.paths[0], trimmed[0], self.keep)
        self._trimmed += [p for p in trimmed if p in self.paths]

    def _write(self, data: bytes) -> None:
        """Write all of ``data`` to the part, or none of it: a full disk takes a line's head and
        refuses the rest (OSError); the head is cut off again, so a stopped part holds exactly
        the :attr:`frames` counted (a buffered part kept the rest to write on its close, and a
        disk with room by then completed a line counted as lost)."""
        view = memoryview(data)
        try:
            while view:
                n = self._f.write(view)
                if not n:
                    raise OSError(errno.ENOSPC, "the disk took nothing of a line")
                view = view[n:]
        except OSError:
            if len(view) < len(data):
                try:
                    os.ftruncate(self._f.fileno(), self._size)
                except OSError:
                    pass
            raise
        self._size += len(data)

    # -- the sink (the frame loop) --------------------------------------------------------------

    def consume(self, frame: Frame) -> None:
        """Write the frame's line to the operating system; never waits for the disk's sync."""
        self._last_t = frame.t
        # what the frames before this one reloaded: a part starting at it carries it
        self._reloaded_before = self._reloaded
        self._reloaded = carried(self._reloaded, frame.consumed.get("reload"))
        self._state_before = self._state
        self._state = self.state_of() if self.state_of is not None else None
        if self._f is not None and (self._check_at is None or frame.t >= self._check_at):
            self._check_at = frame.t + REMOVED_CHECK_S
            self._check_removed()
        if self.failed is not None and not self._resume(frame.t):
            return
        if self._f is None or self._closing:
            return
        d = frame_to_dict(frame, self._t0 if self._t0 is not None else frame.t)
        if self._t0 is None:
            self._t0 = frame.t
        if self._first_in_file:
            d["t0"] = self._t0                    # each part's first frame carries t0
        if self._t0 + d["t"] != frame.t:
            d["t_mono"] = frame.t   # exactness: t0 + t would round differently
        line = _encode(d)
        with self._cv:
            if len(self._unsynced) >= self.max_queue:
                if self._resumed_t is not None and frame.t - self._resumed_t > SLOW_RESUME_MAX_S:
                    self._slow_wait_s = RESUME_EVERY_S
                wait_s = self._slow_wait_s   # a disk slow for good: 60, 120, 240 ... 3600 s
                self._slow_wait_s = min(2.0 * wait_s, SLOW_RESUME_MAX_S)
                self._fail(f"the disk cannot keep up ({self.max_queue} lines waited, the "
                           f"oldest {self.clock() - self._unsynced[0]:.1f} s)", resumable=True,
                           wait_s=wait_s)
                self._cv.notify()
                return
            try:
                if self.max_bytes is not None and not self._first_in_file and \
                        self._size + len(line) > self.max_bytes:
                    self._f.flush()
                    release(self._f)
                    self._retired.append(self._f)
                    self._open_part()
                    d["t0"] = self._t0
                    line = _encode(d)
                self._write(line)
                self._f.flush()
            except OSError as exc:
                self._fail(exc)
                self._cv.notify()
                return
            self._first_in_file = False
            self.frames += 1
            self._unsynced.append(self.clock())
            self._cv.notify()

    def discard(self) -> None:
        """Close and remove what was written (the installation did not start)."""
        with self._cv:
            self._unsynced.clear()
        self._stop_syncer()
        let_go(self._stopped)
        self._stopped = None
        try:
            if self._f is not None:
                self._f.close()
        except OSError:
            pass
        for p in self.paths:
            try:
                p.unlink()
            except OSError:
                pass

    def close(self) -> None:
        """Sync every line written, then close the file."""
        synced = self._stop_syncer()
        let_go(self._stopped)            # a stopped part: the session ended
        self._stopped = None
        if not synced:
            log.error("recording %s: the disk did not sync the last %d lines within 30 s",
                      self.path, len(self._unsynced))
            return
        if self._f is None or self._f.closed:
            return
        try:
            self._f.flush()
            os.fsync(self._f.fileno())
            self._f.close()
        except OSError as exc:
            if self.failed is None:
                self._fail(exc)
            return
        if self._first_in_file and self._drop_empty_part():
            return
        if self.failed is None:   # the session's frames: in its parts, not in the last alone
            parts = (f" in {len(self.paths)} parts, {self.paths[0].name} to {self.path.name}"
                     if len(self.paths) > 1 else "")
            if self._trimmed:
                parts += (f" (the first {len(self._trimmed)} removed as recorder.keep bounds "
                          f"the folder; {len(self.paths) - len(self._trimmed)} kept)")
            log.info("recording %s: %d frames%s", self.paths[0] if parts else self.path,
                     self.frames, parts)

    def _drop_empty_part(self) -> bool:
        """Remove the closed last part when it holds no frame (a run stopped while it was
        built, before its first frame: a header alone, which replay refuses, as the failure
        path removes such a part too). True when nothing of the session is left."""
        empty = self._removed = self.paths.pop()
        try:
            empty.unlink()
        except OSError as exc:
            removed = f"; the file could not be removed: {exc.strerror or exc}"
        else:
            removed = ", the file removed"
            try:
                fsync_folder(self.folder)
            except OSError:
                pass
        if self.frames == 0:
            log.warning("recording %s: stopped before its first frame: nothing recorded%s",
                        empty, removed)
            return True
        if removed.startswith(";"):
            log.warning("recording %s: its last part holds no frame%s", empty, removed)
        return False


def _encode(d: dict[str, Any]) -> bytes:
    return (json.dumps(d, separators=(",", ":"), allow_nan=False) + "\n").encode()
